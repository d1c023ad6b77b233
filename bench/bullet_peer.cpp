#include "bench/bullet_peer.h"

#ifdef SOFTTOUCH_HAVE_BULLET

#include "bench/timer.h"

// Bullet comes in as a system include (see bench/CMakeLists.txt), so its own warnings stay out of
// the strict build.
#include <BulletSoftBody/btDefaultSoftBodySolver.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace softtouch::bench {
namespace {

/// CreateFromTriMesh allocates a vertices² table of bools indexed by an int: past this many vertices
/// the index overflows.
constexpr std::size_t kMaxTriMeshVertices = 46340;

/// A soft-rigid world holding one soft body, torn down in the order Bullet needs (body out of the
/// world before either is deleted, the world before what it points to).
class BulletWorld {
public:
    BulletWorld()
        : m_configuration(std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>()),
          m_dispatcher(std::make_unique<btCollisionDispatcher>(m_configuration.get())),
          m_broadphase(std::make_unique<btDbvtBroadphase>()),
          m_constraintSolver(std::make_unique<btSequentialImpulseConstraintSolver>()),
          m_softBodySolver(std::make_unique<btDefaultSoftBodySolver>()),
          m_world(std::make_unique<btSoftRigidDynamicsWorld>(m_dispatcher.get(), m_broadphase.get(),
                                                              m_constraintSolver.get(), m_configuration.get(),
                                                              m_softBodySolver.get())) {
        // The scenario has no gravity. Soft bodies read theirs from the world info, not from the
        // world, and the world info starts at (0, -10, 0): both must be cleared.
        m_world->setGravity(btVector3(0, 0, 0));
        m_world->getWorldInfo().m_gravity.setValue(0, 0, 0);
    }
    ~BulletWorld() {
        if (m_body)
            m_world->removeSoftBody(m_body.get());
    }
    BulletWorld(const BulletWorld&) = delete;
    BulletWorld& operator=(const BulletWorld&) = delete;

    btSoftRigidDynamicsWorld& world() { return *m_world; }
    btSoftBodyWorldInfo& worldInfo() { return m_world->getWorldInfo(); }
    /// Takes ownership of `body` and adds it to the world.
    btSoftBody& adopt(btSoftBody* body) {
        m_body.reset(body);
        m_world->addSoftBody(body);
        return *body;
    }

private:
    std::unique_ptr<btSoftBodyRigidBodyCollisionConfiguration> m_configuration;
    std::unique_ptr<btCollisionDispatcher> m_dispatcher;
    std::unique_ptr<btDbvtBroadphase> m_broadphase;
    std::unique_ptr<btSequentialImpulseConstraintSolver> m_constraintSolver;
    std::unique_ptr<btDefaultSoftBodySolver> m_softBodySolver;
    std::unique_ptr<btSoftRigidDynamicsWorld> m_world;
    std::unique_ptr<btSoftBody> m_body;  // destroyed first, after ~BulletWorld took it out of the world
};

/// Bullet's link stiffness kLST for a spring of `stiffnessNPerM` between two nodes of `nodeMass` kg.
///
/// kLST is not in N/m: a btSoftBody link is a position-based distance constraint, and kLST in [0, 1]
/// is the fraction of its length error removed per solver iteration (Bullet's PSolve_Links moves each
/// end by kLST·C/2 for equal masses). There is no exact mapping to a spring constant. We use the
/// XPBD equivalence (Macklin et al. 2016) for one iteration of one constraint: a spring k is the
/// compliance α = 1/k, and XPBD removes the fraction
///     kLST = w / (w + α/dt²) = k·w·dt² / (1 + k·w·dt²),   w = 1/m_a + 1/m_b = 2/m.
/// It is approximate (Bullet sweeps all links Gauss-Seidel, once per step by default), but it keeps
/// what matters for a fair comparison: the same 80 N/m is a soft spring on the heavy nodes of a
/// coarse mesh (kLST ≈ 0.23 at 208 triangles, 1 kg, 240 Hz) and nearly rigid on the light nodes of a
/// fine one (kLST ≈ 0.97 at 24928 triangles), just as it is for the mass-spring contenders. A stiff
/// spring therefore maps to kLST → 1, Bullet's stiffest (inextensible) link.
btScalar linearStiffness(double stiffnessNPerM, double nodeMass, double dt) {
    const double kwdt2 = stiffnessNPerM * (2.0 / nodeMass) * dt * dt;
    return btScalar(std::clamp(kwdt2 / (1.0 + kwdt2), 0.0, 1.0));
}

/// Bullet's damping kDP for the scenario's per-spring damping `dampingNsPerM` on a body of
/// `totalMass` kg.
///
/// kDP is not a spring damper either: after the position solve Bullet sets v = (1 − kDP)·Δx/dt on
/// every node, a drag on absolute velocity ("ether" damping) that also resists the user's pull, which
/// the scenario's dampers (on relative velocity along each spring) never do. We keep it as weak as
/// the scenario allows: the per-step decay that the scenario's damping coefficient would give the
/// whole body, 1 − exp(−c·dt/M) (0.0037 at 0.9 N·s/m, 1 kg, 240 Hz). It does not depend on the mesh
/// resolution, and the position solve dissipates on its own (it discards the velocity a constraint
/// correction would need to overshoot). A larger kDP (0.01–0.1 is common in Bullet's demos) would act as an ether drag of
/// kDP·M/dt = 2.4–24 N·s/m on a 1 kg body, against a drag spring of 0.5 N·s/m.
btScalar dampingCoefficient(double dampingNsPerM, double totalMass, double dt) {
    return btScalar(std::clamp(1.0 - std::exp(-dampingNsPerM * dt / totalMass), 0.0, 1.0));
}

bool allFinite(const std::vector<Vec3f>& positions) {
    return std::all_of(positions.begin(), positions.end(), [](const Vec3f& p) { return p.allFinite(); });
}

}  // namespace

bool bulletAvailable() { return true; }

std::optional<TimingResult> timeBulletSoftBody(const InteractionScenario& s) {
    const Mesh& mesh = s.mesh;
    const std::size_t vertexCount = mesh.positions.size();
    if (mesh.triangles.empty() || vertexCount > kMaxTriMeshVertices)
        return std::nullopt;

    BulletWorld bullet;

    // Nodes per vertex, links along triangle edges: the topology of the global mass-spring contender.
    std::vector<btScalar> vertices;
    vertices.reserve(3 * vertexCount);
    for (const Vec3f& p : mesh.positions) {
        vertices.push_back(btScalar(p.x()));
        vertices.push_back(btScalar(p.y()));
        vertices.push_back(btScalar(p.z()));
    }
    std::vector<int> triangles;
    triangles.reserve(3 * mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        for (std::uint32_t index : t)
            triangles.push_back(int(index));
    }
    // randomizeConstraints = true is Bullet's default: the links are shuffled once, so the one
    // Gauss-Seidel sweep per step has no directional bias from the mesh's vertex order.
    btSoftBody& body = bullet.adopt(btSoftBodyHelpers::CreateFromTriMesh(
        bullet.worldInfo(), vertices.data(), triangles.data(), int(mesh.triangles.size()), true));
    // CreateFromTriMesh makes as many nodes as the largest index used: an unreferenced last vertex
    // would be missing.
    if (std::size_t(body.m_nodes.size()) != vertexCount)
        return std::nullopt;
    // No generateBendingConstraints(): bending links would join vertices two edges apart, which the
    // mass-spring contenders do not have. The closed surface holds its shape through its edges only,
    // exactly as theirs does, and every contender solves the same number of springs.

    const double nodeMass = s.totalMass / double(vertexCount);
    btSoftBody::Material& material = *body.m_materials[0];
    material.m_kLST = linearStiffness(s.stiffness, nodeMass, s.dt);
    body.m_cfg.kDP = dampingCoefficient(s.damping, s.totalMass, s.dt);
    // Solver iterations stay at Bullet's defaults (one position iteration, no velocity or drift
    // iterations): what a game developer gets, and the cheapest setting, so Bullet is never
    // handicapped in time. setTotalMass spreads the mass evenly over the nodes (same per-vertex mass
    // as the mass-spring contenders); zero mass then makes the held vertices static.
    body.setTotalMass(btScalar(s.totalMass), false);
    for (std::uint32_t a : s.anchors)
        body.setMass(int(a), 0);
    // Self-collision is off by default (fCollision::Default = rigid-soft only) and there are no rigid
    // bodies: no contender pays for collisions.

    const btSoftBody::Node& dragged = body.m_nodes[int(s.dragVertex)];
    const Vec3 restPoint = mesh.positions[s.dragVertex].cast<double>();
    std::vector<Vec3f> positions(vertexCount);
    const int steps = int(std::lround(s.seconds / s.dt));
    const int perFrame = std::max(1, int(std::lround(1.0 / (s.frameRate * s.dt))));

    // Timed: the stepping and the position reads the screen needs, as for every contender. Not timed:
    // creating the world and the soft body (CreateFromTriMesh fills a vertices² table, a one-off cost
    // that says nothing about interaction).
    TimingResult result;
    Stopwatch watch;
    for (int i = 0; i < steps; ++i) {
        // The user's drag spring. Bullet integrates node forces explicitly (v += h·f/m in
        // predictMotion), and the plain F = Ks·(target − x) − Kd·v is unstable once h·Kd/m > 2: on the
        // 12466 light nodes of 24928 triangles h·Kd/m = 26 and the dragged vertex flies off (lowering
        // kLST makes it worse, not better). So the force is the one that gives the node, alone, the
        // velocity of implicit Euler on its drag spring (Baraff & Witkin 1998):
        //   (m + h·Kd + h²·Ks)·Δv = h·(Ks·(target − x − h·v) − Kd·v),   F = m·Δv/h,
        // unconditionally stable, and F → Ks·(target − x) − Kd·v as h → 0. The mass-spring
        // contenders treat the drag implicitly too.
        const Vec3 target = restPoint + s.dragOffsetAt(i * s.dt);
        const Vec3 x(dragged.m_x.x(), dragged.m_x.y(), dragged.m_x.z());
        const Vec3 v(dragged.m_v.x(), dragged.m_v.y(), dragged.m_v.z());
        const double h = s.dt;
        const Vec3 force = (s.dragStiffness * (target - x - h * v) - s.dragDamping * v) /
                           (1.0 + (h * s.dragDamping + h * h * s.dragStiffness) / nodeMass);
        body.addForce(btVector3(btScalar(force.x()), btScalar(force.y()), btScalar(force.z())), int(s.dragVertex));
        // maxSubSteps = 0: one step of exactly dt, no interpolation: a fixed step, like ours.
        bullet.world().stepSimulation(btScalar(s.dt), 0);
        if ((i + 1) % perFrame == 0) {
            for (std::size_t n = 0; n < vertexCount; ++n) {
                const btVector3& p = body.m_nodes[int(n)].m_x;
                positions[n] = Vec3f(float(p.x()), float(p.y()), float(p.z()));
            }
            result.finite = result.finite && allFinite(positions);
        }
    }
    result.seconds = watch.seconds();
    result.dragVertexEnd = Vec3(dragged.m_x.x(), dragged.m_x.y(), dragged.m_x.z());
    result.finite = result.finite && result.dragVertexEnd.allFinite();
    return result;
}

}  // namespace softtouch::bench

#else  // !SOFTTOUCH_HAVE_BULLET

namespace softtouch::bench {

bool bulletAvailable() { return false; }

std::optional<TimingResult> timeBulletSoftBody(const InteractionScenario& /*scenario*/) { return std::nullopt; }

}  // namespace softtouch::bench

#endif
