#include "bench/solid_reference.h"

#include "analysis/trajectory_error.h"
#include "core/geometry/oriented_box.h"
#include "core/solver/simulator.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace softtouch::bench {
namespace {

constexpr double kSolidSettleStep = 1.0 / 30.0;  ///< Implicit Euler: its numerical damping is welcome here.
constexpr int kSolidSettleSteps = 1200;           ///< At most: 40 s of holding.
constexpr double kSolidStillFraction = 1e-6;      ///< Of the displacement per step: the point has stopped.
constexpr int kSolidStillSteps = 5;               ///< That many steps in a row.

std::string net(int n) {
    return std::to_string(n) + "x" + std::to_string(n) + "x" + std::to_string(n);
}

}  // namespace

StaticResponse settleSolid(const InteractionScenario& s, double scale, int nodes) {
    const OurBody body(s, Contender::Solid, scale, nodes);
    SimulationSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    settings.dt = kSolidSettleStep;
    settings.sleep = false;
    Simulator sim(body.sharedModel(), settings);
    const Vec3 rest = body.gripRest();
    DragSpring drag = body.dragSpring(s);
    drag.target = rest + s.dragOffset;
    ExternalForces forces;
    forces.drags.assign(1, drag);
    StaticResponse r;
    double last = 0.0;
    int still = 0;
    while (r.steps < kSolidSettleSteps && still < kSolidStillSteps) {
        (void)sim.step(forces);
        ++r.steps;
        const double d = (body.gripPoint(sim.state().position) - rest).norm();
        still = std::abs(d - last) <= kSolidStillFraction * d ? still + 1 : 0;
        last = d;
    }
    r.displacement = last;
    r.converged = still >= kSolidStillSteps;
    return r;
}

SolidReference solidReference(const InteractionScenario& s, double target, double firstScale,
                              const SolidReferenceOptions& options, std::ostream& log) {
    SolidReference reference;
    const int finest = options.nodes.back();
    reference.calibration = calibrate(
        [&](double scale) {
            const StaticResponse r = settleSolid(s, scale, finest);
            return CalibrationStep{scale, r.displacement, r.steps};
        },
        target, s.dragOffset.norm(), firstScale, kEqualResponseTolerance, kEqualResponseEvaluations);
    const double scale = reference.calibration.scale;
    reference.material = solidMaterial(s, fitBox(s.mesh.positions).value().size, scale);
    const double diagonal = s.mesh.bounds().diagonal();
    char line[240];
    std::snprintf(line, sizeof line, "    solid    E %.4g Pa, viscosity %.4g Pa*s -> static %.4f m, %s in %zu settles (",
                  reference.material.modulus, reference.material.viscosity, reference.calibration.displacement,
                  reference.calibration.converged ? "converged" : "NOT converged", reference.calibration.steps.size());
    log << line;
    for (std::size_t i = 0; i < reference.calibration.steps.size(); ++i) {
        const CalibrationStep& step = reference.calibration.steps[i];
        std::snprintf(line, sizeof line, "%s%.3g -> %.4f in %d steps", i ? ", " : "", step.scale, step.displacement, step.settleSteps);
        log << line;
    }
    log << ")\n" << std::flush;

    std::vector<Vec3f> previous;
    auto rung = [&](int nodes, int division) {
        const OurBody body(s, Contender::Solid, scale, nodes);
        ContenderRun run = runContender(s, body, {IntegratorKind::Verlet, 1, division});
        analysis::ReferenceLevel level;
        level.what = "solid " + net(nodes) + " bezier, verlet, dt 1/" +
                     std::to_string(int(std::lround(division / s.dt)));
        level.seconds = run.seconds;
        level.change = previous.empty() ? std::numeric_limits<double>::quiet_NaN()
                                        : analysis::trajectoryError(run.frames, previous, diagonal);
        log << "    ";
        analysis::logReferenceLevel(level, log);
        reference.levels.push_back(level);
        previous = std::move(run.frames);
    };
    // Time first, on the coarsest net; then the nets at the reference's step, coarsest first.
    rung(options.nodes.front(), 2 * options.stepDivision);
    std::vector<double> spaceChanges;
    for (std::size_t i = 0; i < options.nodes.size(); ++i) {
        rung(options.nodes[i], options.stepDivision);
        if (i > 0)
            spaceChanges.push_back(reference.levels.back().change);
    }
    reference.frames = std::move(previous);
    reference.uncertainty = analysis::refinementUncertainty(spaceChanges, reference.levels[1].change);
    reference.description = "solid " + net(finest) + " bezier, verlet, dt 1/" +
                            std::to_string(int(std::lround(options.stepDivision / s.dt)));
    std::snprintf(line, sizeof line, "    reference: %s; %.3g%% of the diagonal from the limit (space %.3g%%%s, step %.3g%%)\n",
                  reference.description.c_str(), 100.0 * reference.uncertainty.total, 100.0 * reference.uncertainty.space,
                  reference.uncertainty.spaceConverging ? "" : ", not shrinking", 100.0 * reference.uncertainty.time);
    log << line << std::flush;
    return reference;
}

}  // namespace softtouch::bench
