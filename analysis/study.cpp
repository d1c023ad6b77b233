#include "analysis/study.h"

#include "analysis/timer.h"
#include "analysis/trajectory_error.h"
#include "core/solid_modes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace softtouch::analysis {
namespace {

using Frames = std::vector<Vec3f>;  ///< Mesh positions of every frame, one frame after another.

/// The object rebuilt on another lattice over the same box, material carried over as a continuum.
Result<SceneObject> onLattice(const SceneObject& source, const LatticeShape& shape) {
    auto lattice = Lattice::create(shape, source.lattice.box());
    if (!lattice)
        return Status::error(lattice.message());
    SceneObject o = source;
    o.lattice = std::move(lattice.value());
    o.material = resampleMaterial(source.lattice, source.material, o.lattice, true);
    return o;
}

/// Mesh frames at `fps` over `seconds` of driven simulation, and the wall time of the physics.
struct DrivenRun {
    Frames frames;
    int frameCount = 0;
    double physicsSeconds = 0.0;
    bool finite = true;
};

/// Runs the first object of `scene` through the same SceneSimulation a bake uses (its drivers, the
/// scene's world and simulation settings). Frames are evaluated only when `keepFrames`.
DrivenRun runDriven(const Scene& scene, double seconds, double fps, bool keepFrames = true) {
    auto sim = SceneSimulation::create(scene);
    DrivenRun run;
    if (!sim) {
        run.finite = false;
        return run;
    }
    const std::size_t vertices = scene.objects.front().mesh->positions.size();
    // Frame f at f / fps from f = 0 (the rest pose), as a bake writes them.
    const int frames = int(std::lround(seconds * fps));
    if (keepFrames)
        run.frames.resize(std::size_t(frames) * vertices);
    for (int f = 0; f < frames; ++f) {
        Stopwatch watch;
        sim->advanceTo(double(f) / fps);
        run.physicsSeconds += watch.seconds();
        if (!keepFrames)
            continue;
        const std::span<Vec3f> positions(run.frames.data() + std::size_t(f) * vertices, vertices);
        sim->evaluate(0, positions, {}, 0);
        for (const Vec3f& p : positions)
            run.finite = run.finite && p.allFinite();
        ++run.frameCount;
    }
    return run;
}

/// The scene with only its first object, on the given integrator and step.
Scene withSetting(const Scene& scene, const SceneObject& object, IntegratorKind integrator, double dt) {
    Scene s;
    s.objects = {object};
    s.world = scene.world;
    s.world.simulation.integrator = integrator;
    s.world.simulation.dt = dt;
    return s;
}

/// RMS and largest distance between two runs / diagonal; NaN when they do not hold the same frames (a run
/// that failed to start).
TrajectoryDistance distance(const Frames& a, const Frames& b, double diagonal) {
    if (a.size() != b.size())
        return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    return trajectoryDistance(a, b, diagonal);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Free vibration of the undamped body from a bent shape: energy drift, amplitude loss, frequency.
struct FreeRun {
    double energyDrift = 0.0;
    double amplitudeRatio = 1.0;  ///< Last over first complete half-period amplitude.
    double periods = 0.0;         ///< Periods between them.
    double frequency = 0.0;
};

FreeRun runFree(const SceneObject& object, IntegratorKind integrator, double dt, double seconds) {
    LatticeMaterial m = object.material;
    m.damping.assign(m.damping.size(), 0.0);
    m.nodeDamping.assign(m.mass.size(), 0.0);
    const auto model = buildLatticeBody(object.lattice, m).value();
    SimulationSettings settings;
    settings.integrator = integrator;
    settings.dt = dt;
    settings.sleep = false;
    Simulator sim(model, settings);
    // Bend the body sideways (roughly its lowest lateral mode): w-displacement growing away from u = 1.
    BodyState start = sim.saveState();
    const OrientedBox& box = object.lattice.box();
    for (int n = 0; n < object.lattice.nodeCount(); ++n) {
        if (model->inverseMass[std::size_t(n)] == 0.0)
            continue;
        const Vec3 uvw = object.lattice.restNodeParameters(n);
        start.position[std::size_t(n)] += box.axes.col(2) * (0.03 * box.diagonal() * std::sin(0.5 * std::numbers::pi * (1.0 - uvw.x())));
    }
    sim.restoreState(start);
    const ExternalForces none;
    auto energy = [&] { return kineticEnergy(*model, sim.state()) + springEnergy(*model, sim.state()); };
    const double e0 = energy();
    // The lateral displacement of the whole body (mass-weighted), which the bent shape excites most.
    auto lateral = [&] {
        double sum = 0.0, mass = 0.0;
        for (std::size_t n = 0; n < model->nodeCount(); ++n) {
            if (model->inverseMass[n] == 0.0)
                continue;
            sum += model->mass[n] * (sim.state().position[n] - model->restPositions[n]).dot(box.axes.col(2));
            mass += model->mass[n];
        }
        return sum / mass;
    };
    // Zero crossings in both directions (half periods) and the largest |x| within each half period.
    std::vector<double> crossings, amplitudes;
    double previous = lateral(), peak = 0.0;
    const long long steps = std::llround(seconds / dt);
    for (long long i = 0; i < steps; ++i) {
        (void)sim.step(none);
        const double x = lateral();
        peak = std::max(peak, std::abs(x));
        if ((previous < 0.0) != (x < 0.0)) {
            crossings.push_back(sim.time() - dt * x / (x - previous));
            if (crossings.size() >= 2)
                amplitudes.push_back(peak);  // a complete half period
            peak = 0.0;
        }
        previous = x;
    }
    FreeRun r;
    r.energyDrift = e0 > 0.0 ? (energy() - e0) / e0 : 0.0;
    if (crossings.size() >= 3)
        r.frequency = 0.5 * double(crossings.size() - 1) / (crossings.back() - crossings.front());
    if (amplitudes.size() >= 2 && amplitudes.front() > 0.0) {
        r.amplitudeRatio = amplitudes.back() / amplitudes.front();
        r.periods = 0.5 * double(amplitudes.size() - 1);
    }
    return r;
}

}  // namespace

std::string_view studyErrorName(StudyError kind) {
    switch (kind) {
    case StudyError::Total: return "total";
    case StudyError::Integration: return "integration";
    case StudyError::Model: return "model";
    }
    return "total";
}

std::optional<StudyError> parseStudyError(std::string_view name) {
    for (StudyError k : {StudyError::Total, StudyError::Integration, StudyError::Model})
        if (studyErrorName(k) == name)
            return k;
    return std::nullopt;
}

double StudyRow::error(StudyError kind) const {
    return kind == StudyError::Integration ? timeError : kind == StudyError::Model ? modelError : rmsError;
}

double Remeasured::error(StudyError kind) const {
    return kind == StudyError::Integration ? integration : kind == StudyError::Model ? model : total;
}

std::string latticeShapeName(const LatticeShape& s) {
    return std::to_string(s.nodes[0]) + "x" + std::to_string(s.nodes[1]) + "x" + std::to_string(s.nodes[2]) +
           (s.kind == LatticeKind::Bezier ? " bezier" : " bspline");
}

StudySetting sceneSetting(const Scene& scene) {
    return {scene.world.simulation.integrator, scene.world.simulation.dt, scene.objects.front().lattice.shape()};
}

bool sameSetting(const StudySetting& a, const StudySetting& b) {
    return a.integrator == b.integrator && std::abs(a.dt - b.dt) <= 1e-12 * b.dt && a.lattice == b.lattice;
}

Result<Scene> applySetting(const Scene& scene, const StudySetting& setting) {
    if (scene.objects.empty())
        return Status::error("the scene has no object");
    auto moved = onLattice(scene.objects.front(), setting.lattice);
    if (!moved)
        return Status::error(moved.message());
    Scene out = scene;
    out.objects.front() = std::move(moved.value());
    out.world.simulation.integrator = setting.integrator;
    out.world.simulation.dt = setting.dt;
    return out;
}

StudyResult runStudy(const Scene& scene, const StudyOptions& options, std::ostream& log) {
    StudyResult result;
    result.error = options.error;
    if (scene.objects.empty())
        return result;  // nothing to measure: no rows
    const SceneObject& source = scene.objects.front();
    result.fps = scene.world.fps;
    result.seconds = options.seconds > 0.0 ? options.seconds : double(scene.world.frames) / scene.world.fps;
    const double seconds = result.seconds, fps = result.fps;
    const int repeats = std::clamp(options.repeats, 1, 100);
    std::vector<double> steps = {1.0 / 1000, 1.0 / 480, 1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 24};
    std::vector<LatticeShape> shapes = {{LatticeKind::Bezier, {2, 2, 2}}, {LatticeKind::Bezier, {3, 3, 3}},
                                        {LatticeKind::Bezier, {4, 4, 4}}, {LatticeKind::Bezier, {6, 6, 6}},
                                        {LatticeKind::Bezier, {8, 8, 8}}, {LatticeKind::BSpline, {6, 6, 6}},
                                        {LatticeKind::BSpline, {8, 8, 8}}};
    if (options.quick) {
        steps = {1.0 / 240, 1.0 / 60, 1.0 / 24};
        shapes = {{LatticeKind::Bezier, {3, 3, 3}}, {LatticeKind::Bezier, {4, 4, 4}}, {LatticeKind::BSpline, {6, 6, 6}}};
    }
    std::vector<IntegratorKind> kinds = {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                         IntegratorKind::Xpbd};
    if (!options.lattices.empty())
        shapes = options.lattices;
    if (!options.integrators.empty())
        kinds = options.integrators;
    if (!options.steps.empty())
        steps = options.steps;
    std::vector<StudySetting> settings;
    for (const LatticeShape& shape : shapes)
        for (IntegratorKind kind : kinds)
            for (double dt : steps)
                settings.push_back({kind, dt, shape});
    const StudySetting current = sceneSetting(scene);
    if (options.includeCurrent &&
        std::none_of(settings.begin(), settings.end(), [&](const StudySetting& s) { return sameSetting(s, current); }))
        settings.push_back(current);

    // Reference: the finest Bezier lattice SoftTouch builds (8x8x8, degree 7), central differences
    // (second order) at a tiny step; halving the step again says how converged it is. The Bezier family
    // converges towards it monotonically (test_study); B-spline nets converge to a limit a few 1e-3 of the
    // diagonal away (their nodes crowd at the faces), which their model error shows.
    const LatticeShape referenceShape{LatticeKind::Bezier, {8, 8, 8}};
    result.referenceDt = 1.0 / 4000;
    const SceneObject referenceObject = onLattice(source, referenceShape).value();
    // The reference runs are the longest of the study: a cancel is honoured between them too.
    auto cancelled = [&] { return options.progress && !options.progress(0.0); };
    if (cancelled()) {
        result.cancelled = true;
        return result;
    }
    const DrivenRun reference =
        runDriven(withSetting(scene, referenceObject, IntegratorKind::Verlet, result.referenceDt), seconds, fps);
    if (cancelled()) {
        result.cancelled = true;
        return result;
    }
    const DrivenRun finer =
        runDriven(withSetting(scene, referenceObject, IntegratorKind::Verlet, result.referenceDt / 2), seconds, fps);
    const double diagonal = source.lattice.box().diagonal();
    result.referenceUncertainty = distance(reference.frames, finer.frames, diagonal).rms;
    result.reference = latticeShapeName(referenceShape) + ", verlet, dt = 1/" + std::to_string(int(std::lround(1.0 / result.referenceDt))) + " s";
    result.referenceFrames = std::make_shared<const Frames>(reference.frames);
    Frames rest;
    for (int f = 0; f < reference.frameCount; ++f)
        rest.insert(rest.end(), source.mesh->positions.begin(), source.mesh->positions.end());
    const TrajectoryDistance still = distance(rest, reference.frames, diagonal);
    result.restError = still.rms;
    result.motionAmplitude = still.max;
    log << "reference: " << result.reference << " (halving its dt changes it by " << result.referenceUncertainty
        << " of the diagonal, RMS)\n"
        << "clip: " << seconds << " s at " << fps << " fps; the mesh moves up to " << result.motionAmplitude
        << " of the diagonal; doing nothing (the rest pose) scores " << result.restError << " (RMS)\n";

    const double freeSeconds = options.quick ? 2.0 : 3.0;  // several periods of the lowest lateral mode
    // Per lattice: converged in time (the reference of the integration error and of the frequency), and
    // its model error. Even exact integration trades amplitude between modes, so amplitude loss is
    // measured against the converged free vibration.
    struct LatticeRuns {
        SceneObject object;
        DrivenRun converged;
        double modelError = 0.0;
        FreeRun free;
        std::vector<double> solidModeError;
    };
    std::vector<std::pair<LatticeShape, std::shared_ptr<LatticeRuns>>> lattices;
    auto runsFor = [&](const LatticeShape& shape) -> std::shared_ptr<LatticeRuns> {
        for (auto& [s, runs] : lattices)
            if (s == shape)
                return runs;
        auto runs = std::make_shared<LatticeRuns>();
        auto object = onLattice(source, shape);
        if (!object)
            return nullptr;
        runs->object = std::move(object.value());
        runs->converged = runDriven(withSetting(scene, runs->object, IntegratorKind::Verlet, result.referenceDt), seconds, fps);
        runs->modelError = distance(runs->converged.frames, reference.frames, diagonal).rms;
        runs->free = runFree(runs->object, IntegratorKind::Verlet, result.referenceDt, freeSeconds);
        if (auto compared = compareWithSolid(runs->object.lattice, runs->object.material))
            runs->solidModeError = compared->error;  // empty unless the solid converged
        lattices.emplace_back(shape, runs);
        log << "  " << latticeShapeName(shape) << ": model error " << runs->modelError << " (RMS / diagonal)";
        if (!runs->solidModeError.empty())
            log << "; modes against the solid " << describeModeErrors(runs->solidModeError);
        log << "\n";
        return runs;
    };

    for (std::size_t i = 0; i < settings.size(); ++i) {
        if (options.progress && !options.progress(double(i) / double(settings.size()))) {
            result.cancelled = true;
            break;
        }
        const StudySetting& setting = settings[i];
        const auto runs = runsFor(setting.lattice);
        if (!runs)
            continue;
        StudyRow row;
        row.integrator = setting.integrator;
        row.dt = setting.dt;
        row.lattice = setting.lattice;
        row.resolution = latticeShapeName(setting.lattice);
        row.nodes = runs->object.lattice.nodeCount();
        row.current = sameSetting(setting, current);
        const Scene run = withSetting(scene, runs->object, setting.integrator, setting.dt);
        const DrivenRun driven = runDriven(run, seconds, fps);
        std::vector<double> costs{driven.physicsSeconds / seconds};
        for (int r = 1; r < repeats; ++r)
            costs.push_back(runDriven(run, seconds, fps, false).physicsSeconds / seconds);
        row.costPerSecond = median(costs);
        row.costSpread = row.costPerSecond > 0.0
                             ? (*std::max_element(costs.begin(), costs.end()) - *std::min_element(costs.begin(), costs.end())) / row.costPerSecond
                             : 0.0;
        row.finite = driven.finite && driven.frames.size() == reference.frames.size();
        const TrajectoryDistance total = distance(driven.frames, reference.frames, diagonal);
        row.rmsError = total.rms;
        row.maxError = total.max;
        row.timeError = distance(driven.frames, runs->converged.frames, diagonal).rms;
        row.modelError = runs->modelError;
        row.solidModeError = runs->solidModeError;
        const FreeRun free = runFree(runs->object, setting.integrator, setting.dt, freeSeconds);
        row.energyDrift = free.energyDrift;
        if (free.periods > 0.0 && runs->free.amplitudeRatio > 0.0)
            row.amplitudeLoss = 1.0 - std::pow(std::max(0.0, free.amplitudeRatio / runs->free.amplitudeRatio), 1.0 / free.periods);
        row.frequencyError = runs->free.frequency > 0.0 && free.frequency > 0.0
                                 ? free.frequency / runs->free.frequency - 1.0
                                 : std::numeric_limits<double>::quiet_NaN();  // no oscillation seen
        result.rows.push_back(row);
        char line[260];
        std::snprintf(line, sizeof line,
                      "  %-14s %-17s dt 1/%-4d  cost %9.2e s/s (±%3.0f%%)  error %8.2e (time %8.2e, model %8.2e)  "
                      "energy %+8.1e  loss/period %6.3f  freq %+7.3f%s\n",
                      row.resolution.c_str(), std::string(integratorName(row.integrator)).c_str(), int(std::lround(1 / row.dt)),
                      row.costPerSecond, 50.0 * row.costSpread, row.rmsError, row.timeError, row.modelError, row.energyDrift,
                      row.amplitudeLoss, row.frequencyError, row.current ? "  (the scene's own)" : "");
        log << line << std::flush;
    }
    if (options.progress && !result.cancelled)
        options.progress(1.0);
    markPareto(result);
    return result;
}

void markPareto(StudyResult& result) {
    for (StudyRow& a : result.rows) {
        a.pareto = a.finite && std::none_of(result.rows.begin(), result.rows.end(), [&](const StudyRow& b) {
                       const double ea = a.error(result.error), eb = b.error(result.error);
                       return &b != &a && b.finite && b.costPerSecond <= a.costPerSecond && eb <= ea &&
                              (b.costPerSecond < a.costPerSecond || eb < ea);
                   });
    }
}

const StudyRow* cheapestWithin(const StudyResult& result, double target) {
    const StudyRow* best = nullptr;
    for (const StudyRow& r : result.rows) {
        if (r.finite && r.error(result.error) <= target && (!best || r.costPerSecond < best->costPerSecond))
            best = &r;
    }
    return best;
}

Result<Remeasured> remeasure(const Scene& scene, const StudyResult& study) {
    if (scene.objects.empty() || !study.referenceFrames)
        return Status::error("nothing to measure: no object or no reference");
    const double diagonal = scene.objects.front().lattice.box().diagonal();
    const DrivenRun run = runDriven(scene, study.seconds, study.fps);
    const DrivenRun converged =
        runDriven(withSetting(scene, scene.objects.front(), IntegratorKind::Verlet, study.referenceDt), study.seconds, study.fps);
    if (!run.finite || run.frames.size() != study.referenceFrames->size() || converged.frames.size() != run.frames.size())
        return Status::error("the scene does not run to the study's clip with the study's mesh");
    Remeasured r;
    r.total = distance(run.frames, *study.referenceFrames, diagonal).rms;
    r.integration = distance(run.frames, converged.frames, diagonal).rms;
    r.model = distance(converged.frames, *study.referenceFrames, diagonal).rms;
    return r;
}

double worstModeError(const std::vector<double>& errors) {
    double worst = 0.0;
    for (double e : errors)
        worst = std::max(worst, std::abs(e));
    return worst;
}

std::string studyCsv(const StudyResult& result) {
    std::ostringstream out;
    out << "integrator,dt_s,resolution,nodes,cost_s_per_s,cost_spread,rms_error,max_error,time_error,model_error,"
           "energy_drift,amplitude_loss_per_period,frequency_error,finite,pareto,current,solid_mode_error\n";
    for (const StudyRow& r : result.rows) {
        out << integratorName(r.integrator) << ',' << r.dt << ',' << r.resolution << ',' << r.nodes << ',' << r.costPerSecond
            << ',' << r.costSpread << ',' << r.rmsError << ',' << r.maxError << ',' << r.timeError << ',' << r.modelError << ','
            << r.energyDrift << ',' << r.amplitudeLoss << ',' << r.frequencyError << ',' << (r.finite ? 1 : 0) << ','
            << (r.pareto ? 1 : 0) << ',' << (r.current ? 1 : 0) << ',';
        if (!r.solidModeError.empty())  // the largest of the three; empty: no converged solid
            out << worstModeError(r.solidModeError);
        out << '\n';
    }
    return out.str();
}

std::string studyMarkdown(const StudyResult& result, const std::string& command) {
    std::ostringstream out;
    auto row = [&](const StudyRow& r) {
        char line[320];
        std::snprintf(line, sizeof line, "| %s | 1/%d | %s | %.2e ±%.0f%% | %.2e | %.2e | %.2e | %.2e | %+.1e | %.3f | %+.3f |%s\n",
                      std::string(integratorName(r.integrator)).c_str(), int(std::lround(1.0 / r.dt)), r.resolution.c_str(),
                      r.costPerSecond, 50.0 * r.costSpread, r.rmsError, r.timeError, r.modelError, r.maxError, r.energyDrift,
                      r.amplitudeLoss, r.frequencyError, r.pareto ? " ★ |" : " |");
        out << line;
    };
    const char* header = "| integrator | dt (s) | lattice | cost (s per simulated s) | total error | integration error | "
                         "model error | max error | energy drift | amplitude lost / period | frequency error | Pareto |\n"
                         "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    out << "# Speed against accuracy\n\nMade by `" << command << "`.\n\n"
        << "Every integrator × time step × lattice resolution simulates the same scene (its drivers, anchors and material,\n"
        << "carried to each resolution as the same continuum: density, Young's modulus and viscosity do not depend on the\n"
        << "lattice; anchors keep their extent in the material) for the scene's clip, " << result.seconds << " s at "
        << result.fps << " fps.\n\n"
        << "- **cost**: wall seconds of physics per simulated second (one thread; mesh evaluation excluded), the median of\n"
        << "  repeated runs, ± half their spread.\n"
        << "- **integration error**: mesh vertex distance at every frame to this very lattice converged in time (Verlet at\n"
        << "  1/" << int(std::lround(1.0 / result.referenceDt)) << " s), RMS, relative to the box diagonal: what the integrator and step alone cost.\n"
        << "- **model error**: this lattice converged in time against the reference, the finest lattice converged in time:\n"
        << "  what the resolution alone costs. It is the same for every integrator and step of a lattice.\n"
        << "- **total error**: the run against the reference directly (at most integration + model error). The Pareto front\n"
        << "  and picks use the **" << studyErrorName(result.error) << "** error.\n"
        << "- **reference**: " << result.reference << "; halving its step changes it by " << result.referenceUncertainty
        << " (RMS, relative): errors below that are noise.\n"
        << "- **what the numbers mean**: the mesh moves up to " << result.motionAmplitude
        << " of the diagonal in this clip, and doing nothing\n"
        << "  at all (the rest pose) scores " << result.restError << " RMS: an error is worth having only well below that.\n"
        << "- **free vibration** (damping off, bent sideways and released, the body's mean lateral displacement tracked): energy\n"
        << "  drift over the run; amplitude lost per period beyond what the same lattice converged in time loses (modes trade\n"
        << "  energy even then) — implicit Euler's numerical damping shows here; frequency error against that converged run.\n"
        << "- ★ marks the Pareto front: no other setting is both cheaper and more accurate.\n\n";
    std::vector<const StudyRow*> sorted;
    for (const StudyRow& r : result.rows)
        sorted.push_back(&r);
    std::sort(sorted.begin(), sorted.end(), [](const StudyRow* a, const StudyRow* b) { return a->costPerSecond < b->costPerSecond; });
    out << "## Pareto front\n\n" << header;
    for (const StudyRow* r : sorted)
        if (r->pareto)
            row(*r);
    out << "\n## Model error by lattice\n\nModel error against the finest lattice, and each lattice's three lowest modes "
           "against the converged solid of its material (`softtouch-cli modes --reference`; none where the solid does not "
           "converge):\n\n| lattice | nodes | model error | modes against the solid |\n|---|---|---|---|\n";
    std::vector<std::string> seen;
    for (const StudyRow& r : result.rows) {
        if (std::find(seen.begin(), seen.end(), r.resolution) != seen.end())
            continue;
        seen.push_back(r.resolution);
        char line[160];
        std::snprintf(line, sizeof line, "| %s | %d | %.2e | ", r.resolution.c_str(), r.nodes, r.modelError);
        out << line << (r.solidModeError.empty() ? std::string("none") : describeModeErrors(r.solidModeError)) << " |\n";
    }
    out << "\n## Every setting, cheapest first\n\n" << header;
    for (const StudyRow* r : sorted)
        row(*r);
    return out.str();
}

}  // namespace softtouch::analysis
