#include "analysis/converged_reference.h"

#include "analysis/timer.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace softtouch::analysis {
namespace {

std::string stepName(double dt) {
    return "1/" + std::to_string(int(std::lround(1.0 / dt)));
}

}  // namespace

ReferenceOptions quickReference() {
    ReferenceOptions options;
    options.nodes = {3, 4, 6};
    return options;
}

Result<Scene> solidOnBezier(const Scene& scene, int nodes) {
    Scene out = scene;
    for (SceneObject& object : out.objects) {
        auto lattice = Lattice::create({LatticeKind::Bezier, {nodes, nodes, nodes}}, object.lattice.box());
        if (!lattice)
            return Status::error("object '" + object.name + "': " + lattice.message());
        object.material = resampleMaterial(object.lattice, object.material, lattice.value(), true);
        object.material.element = BodyElement::Solid;
        object.lattice = std::move(lattice.value());
    }
    return out;
}

Result<ConvergedReference> convergedReference(const Scene& scene, const ClipLibrary& library, const Clip& clip,
                                              const ReferenceOptions& options, std::ostream& log) {
    if (clip.source != ClipSource::Drivers)
        return Status::error("clip '" + clip.name + "' plays " + (clip.source == ClipSource::Session ? "a take" : "keys") +
                             " on the lattice's own nodes, which another lattice does not have; the study grades clips of "
                             "the scene's drivers");
    if (options.nodes.empty() || !(options.dt > 0.0))
        return Status::error("the reference needs at least one net and a step");
    const std::vector<double> diagonals = meshDiagonals(scene);
    ConvergedReference reference;
    reference.dt = options.dt;
    const std::size_t runs = options.nodes.size() + 1;
    // Progress through the rungs, and within a rung frame by frame, so a cancel stops a long rung at its
    // next frame rather than at its end.
    auto keepGoing = [&](std::size_t done, double withinRung) {
        return !options.progress || options.progress((double(done) + withinRung) / double(runs));
    };

    // One rung: the scene on an n^3 solid at dt; its change from the rung before.
    ClipMeshFrames previous;
    auto rung = [&](int nodes, double dt, std::size_t done) -> Result<ClipMeshFrames> {
        auto solid = solidOnBezier(scene, nodes);
        if (!solid)
            return Status::error(solid.message());
        solid->world.simulation.integrator = IntegratorKind::Verlet;
        solid->world.simulation.dt = dt;
        ReferenceLevel level;
        level.what = "solid " + std::to_string(nodes) + "x" + std::to_string(nodes) + "x" + std::to_string(nodes) +
                     " bezier, verlet, dt " + stepName(dt) + " s";
        Stopwatch watch;
        auto frames = clipMeshFrames(solid.value(), library, clip, [&](double f) { return keepGoing(done, f); });
        if (frames.wasCancelled())
            return frames.status();
        level.seconds = watch.seconds();
        if (!frames)
            return Status::error("the converged solid (" + level.what + "): " + frames.message());
        level.change = previous.positions.empty() ? std::numeric_limits<double>::quiet_NaN()
                                                  : worstDistance(objectDistances(frames.value(), previous, diagonals));
        logReferenceLevel(level, log);
        reference.levels.push_back(level);
        return frames;
    };

    log << "converged reference: the solid element refined in time on the coarsest net, then in space\n";
    for (const SceneObject& object : scene.objects)
        for (std::size_t d = 0; d < object.drivers.size(); ++d)
            if (!(driverRadius(object.drivers[d]) > 0.0))
                log << "  note: driver " << d + 1 << " of '" << object.name << "' pulls a point: a finer net answers a "
                    << "point's pull with a deeper dent, so the reference converges slowly; a radius on the driver (m) "
                    << "makes its pull a load the solid converges under\n";
    // Time first, on the coarsest net (the cheap one): a finer net substeps at least as finely (its stable
    // step is shorter), so its step error is at most this one's.
    auto coarse = rung(options.nodes.front(), options.dt / 2, 0);
    if (coarse.wasCancelled()) {
        reference.cancelled = true;
        return reference;
    }
    if (!coarse)
        return Status::error(coarse.message());
    previous = std::move(coarse.value());
    std::vector<double> spaceChanges;
    for (std::size_t i = 0; i < options.nodes.size(); ++i) {
        auto frames = rung(options.nodes[i], options.dt, i + 1);
        if (frames.wasCancelled()) {
            reference.cancelled = true;
            return reference;
        }
        if (!frames)
            return Status::error(frames.message());
        if (i > 0)
            spaceChanges.push_back(reference.levels.back().change);
        previous = std::move(frames.value());
    }
    // The first change is the step's (half the step against the full one, same net).
    const double timeChange = reference.levels[1].change;
    reference.frames = std::move(previous);

    const RefinementUncertainty uncertainty = refinementUncertainty(spaceChanges, timeChange);
    reference.spaceConverging = uncertainty.spaceConverging;
    reference.spaceUncertainty = uncertainty.space;
    reference.timeUncertainty = uncertainty.time;
    reference.uncertainty = uncertainty.total;
    reference.description = "solid element on " + std::to_string(options.nodes.back()) + "x" +
                            std::to_string(options.nodes.back()) + "x" + std::to_string(options.nodes.back()) +
                            " bezier, verlet, dt " + stepName(reference.dt) + " s";
    log << "reference: " << reference.description << "; estimated " << reference.uncertainty
        << " of the diagonal from the converged solid (RMS; lattice " << reference.spaceUncertainty
        << (reference.spaceConverging ? "" : ", the changes do not shrink: the last change, no estimate below it")
        << ", step " << reference.timeUncertainty << ")\n";
    return reference;
}

void logReferenceLevel(const ReferenceLevel& level, std::ostream& log) {
    char line[200];
    std::snprintf(line, sizeof line, "  %-44s %7.2f s", level.what.c_str(), level.seconds);
    log << line;
    if (std::isfinite(level.change))
        log << "  moves the mesh " << level.change << " of the diagonal (RMS)";
    log << "\n" << std::flush;
}

RefinementUncertainty refinementUncertainty(std::span<const double> spaceChanges, double timeChange) {
    RefinementUncertainty u;
    // Space: the rest of a geometric series of the changes, or the last change when they do not shrink.
    if (spaceChanges.empty()) {
        u.spaceConverging = false;
        u.space = std::numeric_limits<double>::infinity();  // one net: nothing says how far
    } else if (spaceChanges.size() == 1) {
        u.spaceConverging = false;
        u.space = spaceChanges.back();
    } else {
        const double d1 = spaceChanges[spaceChanges.size() - 2], d2 = spaceChanges.back();
        const double r = d1 > 0.0 ? d2 / d1 : 1.0;
        u.spaceConverging = r < 1.0;
        u.space = u.spaceConverging ? d2 * r / (1.0 - r) : d2;
    }
    // Time: Verlet is second order, so the run at the full step is 4/3 of the change off (e(dt) = C dt²,
    // e(dt/2) = e(dt)/4, change = 3/4 e(dt)).
    u.time = timeChange * 4.0 / 3.0;
    u.total = u.space + u.time;
    return u;
}

double certifiedFrom(const ConvergedReference& reference) {
    return std::isfinite(reference.uncertainty) ? 10.0 * reference.uncertainty : std::numeric_limits<double>::infinity();
}

bool certifiable(const ConvergedReference& reference, double target) {
    return target >= certifiedFrom(reference);
}

}  // namespace softtouch::analysis
