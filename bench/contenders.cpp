#include "bench/contenders.h"

#include "analysis/timer.h"
#include "core/animation/drivers.h"
#include "core/body/lattice_body.h"
#include "core/body/mesh_body.h"
#include "core/solver/simulator.h"

#include <algorithm>
#include <cassert>

namespace softtouch::bench {
namespace {

/// Each held vertex pins the lattice node that moves it most.
void pinAnchors(const InteractionScenario& s, const Lattice& lattice, LatticeMaterial& material) {
    for (std::uint32_t a : s.anchors) {
        const auto weights = lattice.weights(lattice.box().toParameters(s.mesh.positions[a].cast<double>()));
        const auto strongest = std::max_element(weights.begin(), weights.end(),
                                                [](const NodeWeight& x, const NodeWeight& y) { return x.weight < y.weight; });
        material.anchor[strongest->node] = AnchorMode::Pinned;
    }
}

std::shared_ptr<const BodyModel> latticeModel(const InteractionScenario& s, const Lattice& lattice, double scale) {
    LatticeMaterial material =
        uniformMaterial(lattice, s.totalMass / lattice.nodeCount(), scale * s.stiffness, scale * s.damping);
    pinAnchors(s, lattice, material);
    return buildLatticeBody(lattice, material).value();
}

/// The solid element filling the lattice's box: the body's mass spread evenly over the box, the modulus of
/// `scale`, and viscosity / modulus = damping / stiffness. Held by the whole face of the box behind the held
/// vertices (the face of smallest x, makeScenario()'s anchors), which is the same hold on every net: pinning
/// the nodes that move the held vertices most would hold a patch that shrinks as the net is refined, and a
/// finer solid would turn about it ever more freely.
std::shared_ptr<const BodyModel> solidModel(const InteractionScenario& s, const Lattice& lattice, double scale) {
    const Vec3 size = lattice.box().size;
    const SolidMaterial solid = solidMaterial(s, size, scale);
    LatticeMaterial material = continuumMaterial(lattice, s.totalMass / size.prod(), solid.modulus, solid.viscosity);
    material.element = BodyElement::Solid;
    const Vec3 held = lattice.box().toParameters(s.mesh.positions[s.anchors.front()].cast<double>());
    Eigen::Index axis = 0;  // the box axis along which the held vertices lie at one end
    (held.array() - 0.5).abs().maxCoeff(&axis);
    const int end = held[axis] < 0.5 ? 0 : lattice.count(int(axis)) - 1;
    for (int k = 0; k < lattice.count(2); ++k)
        for (int j = 0; j < lattice.count(1); ++j)
            for (int i = 0; i < lattice.count(0); ++i) {
                const int index[3] = {i, j, k};
                if (index[axis] == end)
                    material.anchor[std::size_t(lattice.index(i, j, k))] = AnchorMode::Pinned;
            }
    return buildLatticeBody(lattice, material).value();
}

std::shared_ptr<const BodyModel> meshModel(const InteractionScenario& s, bool local, double scale) {
    MeshBodySettings settings;
    settings.stiffness = scale * s.stiffness;
    settings.damping = scale * s.damping;
    settings.totalMass = s.totalMass;
    settings.anchors = s.anchors;
    if (local) {
        const Vec3f centre = s.mesh.positions[s.dragVertex];
        settings.simulated.resize(s.mesh.positions.size());
        for (std::size_t i = 0; i < s.mesh.positions.size(); ++i)
            settings.simulated[i] = (s.mesh.positions[i] - centre).norm() <= s.localRadius;
    }
    return buildBodyModel(describeMeshBody(s.mesh, settings)).value();
}

}  // namespace

SolidMaterial solidMaterial(const InteractionScenario& s, const Vec3& boxSize, double scale) {
    const double modulus = scale * kSolidModulusPerStiffness * s.stiffness / (boxSize.sum() / 3.0);
    return {modulus, modulus * s.damping / s.stiffness};
}

bool allFinite(std::span<const Vec3f> positions) {
    return std::all_of(positions.begin(), positions.end(), [](const Vec3f& p) { return p.allFinite(); });
}

std::string_view contenderName(Contender contender) {
    switch (contender) {
    case Contender::Lattice: return "lattice";
    case Contender::Global: return "global";
    case Contender::Local: return "local";
    case Contender::Bullet: return "bullet";
    case Contender::Solid: return "solid";
    }
    return "?";
}

OurBody::OurBody(const InteractionScenario& s, Contender contender, double stiffnessScale, int solidNodes) {
    assert(contender != Contender::Bullet && stiffnessScale > 0.0);
    if (contender == Contender::Lattice || contender == Contender::Solid) {
        const LatticeShape shape = contender == Contender::Solid
                                       ? LatticeShape{LatticeKind::Bezier, {solidNodes, solidNodes, solidNodes}}
                                       : LatticeShape{};
        const Lattice lattice = Lattice::create(shape, fitBox(s.mesh.positions).value()).value();
        m_model = contender == Contender::Solid ? solidModel(s, lattice, stiffnessScale)
                                                : latticeModel(s, lattice, stiffnessScale);
        m_binding.emplace(Binding::create(lattice, s.mesh.positions, s.mesh.normals));
        const Vec3 centre = lattice.box().toParameters(s.mesh.positions[s.dragVertex].cast<double>());
        m_gripSupport = materialGrip(lattice, centre, s.gripRadius).support;
    } else {
        m_model = meshModel(s, contender == Contender::Local, stiffnessScale);
        m_gripSupport = surfaceGrip(s);
    }
    m_gripRest = gripPoint(m_model->restPositions);
}

DragSpring OurBody::dragSpring(const InteractionScenario& s) const {
    DragSpring drag;
    drag.support = m_gripSupport;
    drag.stiffness = s.dragStiffness;
    drag.damping = s.dragDamping;
    drag.target = m_gripRest;
    return drag;
}

Vec3 OurBody::gripPoint(const std::vector<Vec3>& nodes) const {
    Vec3 p = Vec3::Zero();
    for (const NodeWeight& w : m_gripSupport)
        p += w.weight * nodes[w.node];
    return p;
}

void OurBody::meshPositions(const std::vector<Vec3>& nodes, std::span<Vec3f> positions) const {
    if (m_binding) {
        m_binding->evaluate(nodes, positions, {}, 1);
        return;
    }
    for (std::size_t v = 0; v < positions.size(); ++v)
        positions[v] = nodes[v].cast<float>();
}

ContenderRun runContender(const InteractionScenario& s, const OurBody& body, const SolverSetting& setting,
                          double budgetSeconds) {
    SimulationSettings settings;
    settings.integrator = setting.integrator;
    settings.dt = s.dt / setting.stepDivision;
    settings.xpbdSubsteps = setting.iterations;
    settings.sleep = false;  // the body is being dragged; do not even test for sleep
    // The mesh bodies are peers, run as their own engines would: without SoftTouch's energy guard, whose
    // rollbacks and extra substeps are SoftTouch's safety net (on the global mass-spring's XPBD at 24,928
    // triangles they made 2 to 16 substeps cost alike). The lattice and the solid run as shipped.
    if (body.isMeshBody())
        settings.energyCheckSteps = 0;
    Simulator sim(body.sharedModel(), settings);

    const Vec3 restPoint = body.gripRest();
    DragSpring drag = body.dragSpring(s);
    ExternalForces forces;
    const std::size_t vertices = s.mesh.positions.size();
    ContenderRun run;
    run.frames.resize(std::size_t(s.frames()) * vertices);  // allocated before the clock starts
    const int perFrame = s.stepsPerFrame(setting.stepDivision);
    run.totalSteps = s.steps(setting.stepDivision);

    analysis::Stopwatch watch;
    while (run.steps < run.totalSteps) {
        drag.target = restPoint + s.dragOffsetAt(run.steps * settings.dt);
        forces.drags.assign(1, drag);
        (void)sim.step(forces);
        if (++run.steps % perFrame == 0) {
            const std::span<Vec3f> out(run.frames.data() + std::size_t(run.framesRun++) * vertices, vertices);
            body.meshPositions(sim.state().position, out);
            if (budgetSeconds > 0.0 && watch.seconds() > budgetSeconds)
                break;
        }
    }
    run.seconds = watch.seconds();
    run.finite = allFinite(std::span<const Vec3f>(run.frames.data(), std::size_t(run.framesRun) * vertices));
    return run;
}

}  // namespace softtouch::bench
