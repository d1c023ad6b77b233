#include "bench/contenders.h"

#include "bench/timer.h"
#include "core/binding.h"
#include "core/lattice_body.h"
#include "core/mesh_body.h"
#include "core/simulator.h"

#include <cmath>

namespace softtouch::bench {
namespace {

int stepsOf(const InteractionScenario& s) { return int(std::lround(s.seconds / s.dt)); }
int stepsPerFrame(const InteractionScenario& s) { return std::max(1, int(std::lround(1.0 / (s.frameRate * s.dt)))); }

SimulationSettings settingsFor(const InteractionScenario& s, IntegratorKind integrator) {
    SimulationSettings settings;
    settings.integrator = integrator;
    settings.dt = s.dt;
    settings.sleep = false;  // the body is being dragged; do not even test for sleep
    return settings;
}

bool allFinite(const std::vector<Vec3f>& v) {
    for (const Vec3f& p : v) {
        if (!p.allFinite())
            return false;
    }
    return true;
}

/// The timed part every contender shares: step with the drag target moving along the scenario, and
/// hand the mesh positions to `frame` at the frame rate. Returns the wall time and finiteness.
template <typename FrameFn>
TimingResult runInteraction(const InteractionScenario& s, Simulator& sim, DragSpring drag, const Vec3& restPoint,
                            std::vector<Vec3f>& positions, FrameFn&& frame) {
    TimingResult result;
    ExternalForces forces;
    const int steps = stepsOf(s), perFrame = stepsPerFrame(s);
    Stopwatch watch;
    for (int i = 0; i < steps; ++i) {
        drag.target = restPoint + s.dragOffsetAt(i * s.dt);
        forces.drags.assign(1, drag);
        (void)sim.step(forces);
        if ((i + 1) % perFrame == 0) {
            frame(positions);
            result.finite = result.finite && allFinite(positions);
        }
    }
    result.seconds = watch.seconds();
    return result;
}

}  // namespace

TimingResult timeLattice(const InteractionScenario& s, IntegratorKind integrator, const LatticeShape& shape) {
    const Lattice lattice = Lattice::create(shape, fitBox(s.mesh.positions).value()).value();
    const int nodes = lattice.nodeCount();
    LatticeMaterial material = uniformMaterial(lattice, s.totalMass / nodes, s.stiffness, s.damping);
    // Each held vertex pins the lattice node that moves it most.
    for (std::uint32_t a : s.anchors) {
        const auto weights = lattice.weights(lattice.box().toParameters(s.mesh.positions[a].cast<double>()));
        const auto strongest = std::max_element(weights.begin(), weights.end(),
                                                [](const NodeWeight& x, const NodeWeight& y) { return x.weight < y.weight; });
        material.anchor[strongest->node] = AnchorMode::Pinned;
    }
    const auto model = buildLatticeBody(lattice, material).value();
    const Binding binding = Binding::create(lattice, s.mesh.positions, s.mesh.normals);
    Simulator sim(model, settingsFor(s, integrator));
    const Vec3 restPoint = s.mesh.positions[s.dragVertex].cast<double>();
    DragSpring drag;
    drag.support = lattice.weights(lattice.box().toParameters(restPoint));
    drag.stiffness = s.dragStiffness;
    drag.damping = s.dragDamping;
    std::vector<Vec3f> positions(s.mesh.positions.size());
    TimingResult result = runInteraction(s, sim, drag, restPoint, positions, [&](std::vector<Vec3f>& out) {
        binding.evaluate(sim.state().position, out, {}, 1);
    });
    binding.evaluate(sim.state().position, positions, {}, 1);
    result.dragVertexEnd = positions[s.dragVertex].cast<double>();
    return result;
}

TimingResult timeMeshSpring(const InteractionScenario& s, IntegratorKind integrator, double localRadius) {
    MeshBodySettings settings;
    settings.stiffness = s.stiffness;
    settings.damping = s.damping;
    settings.totalMass = s.totalMass;
    settings.anchors = s.anchors;
    const Vec3f centre = s.mesh.positions[s.dragVertex];
    if (localRadius > 0.0) {
        settings.simulated.resize(s.mesh.positions.size());
        for (std::size_t i = 0; i < s.mesh.positions.size(); ++i)
            settings.simulated[i] = (s.mesh.positions[i] - centre).norm() <= localRadius;
    }
    const auto model = buildBodyModel(describeMeshBody(s.mesh, settings)).value();
    Simulator sim(model, settingsFor(s, integrator));
    const Vec3 restPoint = centre.cast<double>();
    DragSpring drag;
    drag.support = {{s.dragVertex, 1.0}};
    drag.stiffness = s.dragStiffness;
    drag.damping = s.dragDamping;
    std::vector<Vec3f> positions(s.mesh.positions.size());
    TimingResult result = runInteraction(s, sim, drag, restPoint, positions, [&](std::vector<Vec3f>& out) {
        const auto& x = sim.state().position;
        for (std::size_t v = 0; v < out.size(); ++v)
            out[v] = x[v].cast<float>();
    });
    result.dragVertexEnd = sim.state().position[s.dragVertex];
    return result;
}

}  // namespace softtouch::bench
