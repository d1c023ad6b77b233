#pragma once
/// The contenders of the paper's Table 1 that run on our simulator, each on the same
/// InteractionScenario: the lattice (ours), the global mass-spring and the local one. Bullet, the
/// fourth, is in bullet_peer.h; the solid they are all graded against is built here too
/// (solid_reference.h). A contender is built for one stiffness (the calibration's scale,
/// equal_response.h) and run with one solver setting; a run hands out the mesh at every frame so
/// that runs can be compared (trajectory_error.h).
///
/// One material for all: the scale multiplies every spring's stiffness and its damping alike, so every
/// body has the scenario's relaxation time damping / stiffness (0.9 / 80 s), and the solid has it as
/// viscosity / Young's modulus. Equal response then means the same pull moves what it holds equally far
/// at rest, and the motion on the way there is damped alike.

#include "bench/scenario.h"
#include "core/body/body_model.h"
#include "core/body/forces.h"
#include "core/geometry/binding.h"
#include "core/geometry/lattice.h"
#include "core/solver/integrator.h"

#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace softtouch::bench {

/// Which body simulates the scenario.
enum class Contender : std::uint8_t {
    Lattice, ///< Ours: a 4x4x4 Bezier lattice around the mesh; the mesh follows by free-form deformation.
    Global,  ///< A mass-spring on the mesh: every vertex a node, every edge a spring (the paper's "global").
    Local,   ///< The same, but only the vertices within scenario.localRadius of the drag move (the paper's
             ///< "local mass-spring", its reference 32); the rest of the mesh is pinned.
    Bullet,  ///< Bullet's btSoftBody (bullet_peer.h).
    /// Not a contender but their common reference: the solid element on an n x n x n Bezier net over the
    /// lattice's box, a continuum (solid_reference.h).
    Solid,
};

/// Stable name for reports and JSON ("lattice", "global", "local", "bullet", "solid").
std::string_view contenderName(Contender contender);

/// How a contender is run.
struct SolverSetting {
    IntegratorKind integrator = IntegratorKind::ImplicitEuler; ///< Scheme on our simulator; ignored by Bullet.
    int iterations = 1;    ///< XPBD substeps per step, or Bullet's position iterations per step; ignored by
                           ///< implicit Euler and Verlet. [1, 4096].
    int stepDivision = 1;  ///< Steps per scenario step: dt = scenario.dt / stepDivision (the converged
                           ///< runs take finer steps). [1, 4096].
};

/// What one run of the scenario produced.
struct ContenderRun {
    double seconds = 0.0;      ///< Wall-clock time of the steps run (stepping and the frames' mesh).
    bool finite = true;        ///< Every position handed out was finite.
    std::vector<Vec3f> frames; ///< The mesh at every frame, frame after frame (scenario.frames() × vertices);
                               ///< frames after a stopped run's last stay zero.
    int steps = 0;             ///< Steps run.
    int totalSteps = 0;        ///< Steps of the whole scenario.
    int framesRun = 0;         ///< Frames filled.
    /// Stopped at its time budget before the end of the scenario.
    bool stopped() const { return steps < totalSteps; }
    /// Wall time for the whole scenario: measured, or extrapolated from the steps run.
    double scenarioSeconds() const { return steps > 0 ? seconds * totalSteps / steps : 0.0; }
};

/// Every position finite (ContenderRun::finite, for our bodies and the peer alike).
bool allFinite(std::span<const Vec3f> positions);

/// A body of ours built for one scenario and stiffness, ready to run or settle. Set-up (fitting the
/// lattice, binding, building the springs) happens here, once, and is never timed.
class OurBody {
public:
    /// `stiffnessScale` multiplies scenario.stiffness and scenario.damping on every spring (> 0); for the
    /// solid, kSolidModulus and its viscosity. `contender` is not Bullet. `solidNodes`: the solid's nodes per
    /// axis (Bezier, [2, 8]).
    OurBody(const InteractionScenario& scenario, Contender contender, double stiffnessScale, int solidNodes = 8);

    const BodyModel& model() const { return *m_model; }
    std::shared_ptr<const BodyModel> sharedModel() const { return m_model; }
    /// What the drag holds, as weights over the nodes summing to 1 (the drag spring's support): the ball of
    /// material on the lattice and the solid (materialGrip), the surface under it on a mesh body (surfaceGrip).
    const std::vector<NodeWeight>& gripSupport() const { return m_gripSupport; }
    /// Where the held material is at rest (the support's weighted sum of the rest nodes).
    const Vec3& gripRest() const { return m_gripRest; }
    /// A mass-spring on the mesh (global or local), not a lattice.
    bool isMeshBody() const { return !m_binding; }
    /// The scenario's drag spring on the held material, its target at the material's rest position.
    DragSpring dragSpring(const InteractionScenario& scenario) const;
    /// Where the held material is for these node positions (the support's weighted sum).
    Vec3 gripPoint(const std::vector<Vec3>& nodes) const;
    /// The mesh for these node positions (the lattice evaluates its binding on one thread, like every
    /// contender; a mesh body copies its nodes).
    void meshPositions(const std::vector<Vec3>& nodes, std::span<Vec3f> positions) const;

private:
    std::shared_ptr<const BodyModel> m_model;
    std::optional<Binding> m_binding;  ///< Lattice only.
    std::vector<NodeWeight> m_gripSupport;
    Vec3 m_gripRest = Vec3::Zero();
};

/// The solid's Young's modulus at stiffness scale 1, per N/m of scenario.stiffness and per metre of the
/// box's mean edge: a spring k across a cell of edge h is about the solid E = k / h of that cell, and a
/// 4x4x4 net has h = edge / 3. Only the calibration's first guess depends on it.
inline constexpr double kSolidModulusPerStiffness = 3.0;

/// The solid's material at a stiffness scale, in a box of edges `boxSize`: Young's modulus (Pa) and the
/// viscosity (Pa·s) of the scenario's relaxation time, damping / stiffness.
struct SolidMaterial {
    double modulus = 0.0;
    double viscosity = 0.0;
};
SolidMaterial solidMaterial(const InteractionScenario& scenario, const Vec3& boxSize, double scale);

/// Runs the scenario on `body` with `setting` (timed: the steps and the mesh at every frame). With a
/// `budgetSeconds` > 0 the run stops at the first frame after that much wall time (for a solver too
/// slow to finish within the bench's time; ContenderRun::scenarioSeconds() extrapolates).
ContenderRun runContender(const InteractionScenario& scenario, const OurBody& body, const SolverSetting& setting,
                          double budgetSeconds = 0.0);

}  // namespace softtouch::bench
