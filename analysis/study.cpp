#include "analysis/study.h"

#include "analysis/clip_frames.h"
#include "analysis/timer.h"
#include "analysis/trajectory_error.h"
#include "core/body/forces.h"
#include "core/modes/mode_accuracy.h"
#include "core/modes/modes.h"
#include "core/modes/solid_modes.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace softtouch::analysis {
namespace {

using Frames = std::vector<Vec3f>;  ///< Mesh positions of every frame, one frame after another.

/// The object rebuilt on another lattice over the same box, material carried over as a continuum.
Result<SceneObject> onLattice(const SceneObject& source, const LatticeShape& shape) {
    if (source.lattice.shape() == shape)
        return source;  // its own lattice: the object as authored
    auto lattice = Lattice::create(shape, source.lattice.box());
    if (!lattice)
        return Status::error(lattice.message());
    SceneObject o = source;
    o.lattice = std::move(lattice.value());
    o.material = resampleMaterial(source.lattice, source.material, o.lattice, true);
    return o;
}

/// The clip's mesh frames of a scene, and the wall time they took (physics and deformation, and writing them
/// when a writer is given).
struct ClipRun {
    ClipMeshFrames frames;
    double seconds = 0.0;
    bool finite = true;
    std::string failure;       ///< Why the clip could not be played; empty when it was.
    std::string writeFailure;  ///< Why finite frames could not be written; empty when they were (or nothing writes).
};

ClipRun runClip(const Scene& scene, const ClipLibrary& library, const Clip& clip,
                const std::function<Status(const ClipMeshFrames&)>& write = {}) {
    ClipRun run;
    Stopwatch watch;
    auto frames = clipMeshFrames(scene, library, clip);
    if (!frames) {
        run.seconds = watch.seconds();
        run.finite = false;
        run.failure = frames.message();
        return run;
    }
    run.frames = std::move(frames.value());
    for (const std::vector<Vec3f>& object : run.frames.positions)
        for (const Vec3f& p : object)
            run.finite = run.finite && p.allFinite();
    // A bake refuses non-finite frames before writing them: those runs pay the frames alone.
    if (write && run.finite)
        if (Status s = write(run.frames); !s)
            run.writeFailure = s.message();
    run.seconds = watch.seconds();
    return run;
}

/// The scene with every object on `shape` over its own box and on the setting's element, on the given integrator
/// and step. Refused, naming the object and why, where an object's material cannot run on that element.
Result<Scene> withSetting(const Scene& scene, const StudySetting& setting) {
    Scene out = scene;
    for (SceneObject& object : out.objects) {
        auto moved = onLattice(object, setting.lattice);
        if (!moved)
            return Status::error("object '" + object.name + "': " + moved.message());
        object = std::move(moved.value());
        if (object.material.element != setting.element) {
            object.material.element = setting.element;
            if (auto body = buildLatticeBody(object.lattice, object.material); !body)
                return Status::error("object '" + object.name + "': " + body.message());
        }
    }
    out.world.simulation.integrator = setting.integrator;
    out.world.simulation.dt = setting.dt;
    return out;
}

/// The same scene on Verlet at `dt`: what "converged in time" means for its lattice.
Scene convergedInTime(const Scene& scene, double dt) {
    Scene out = scene;
    out.world.simulation.integrator = IntegratorKind::Verlet;
    out.world.simulation.dt = dt;
    return out;
}

/// Free vibration of the undamped body started in its lowest mode's shape: energy drift, and the motion projected
/// on that mode (q = φᵀ M Δx, which no other mode moves) fitted as one damped oscillation. A count of the zero
/// crossings of some mean displacement would read the solid element's fast modes, which any bent shape excites
/// through its consistent mass, as half periods.
struct FreeRun {
    double energyDrift = 0.0;
    bool oscillates = false;
    double keptPerPeriod = 1.0;   ///< Amplitude kept per period.
    double frequency = 0.0;       ///< Hz.
};

/// The undamped body of an object and its lowest mode: what every free vibration of one lattice starts from
/// (one eigensolve a lattice, not one a row).
struct FreeBody {
    std::shared_ptr<const BodyModel> model;
    VibrationMode mode;
    double amplitude = 0.0;  ///< How far the mode shape's largest node moves at the start, m.
};

std::optional<FreeBody> freeBody(const SceneObject& object) {
    LatticeMaterial m = object.material;
    m.damping.assign(m.damping.size(), 0.0);
    m.nodeDamping.assign(m.mass.size(), 0.0);
    auto built = buildLatticeBody(object.lattice, m);
    if (!built)
        return std::nullopt;
    auto modes = analyseModes(*built.value(), 1);
    if (!modes || modes->modes.empty())
        return std::nullopt;
    return FreeBody{built.value(), modes->modes.front(), 0.03 * object.lattice.box().diagonal()};
}

FreeRun runFree(const std::optional<FreeBody>& body, IntegratorKind integrator, double dt, double seconds) {
    FreeRun r;
    if (!body)
        return r;
    const std::shared_ptr<const BodyModel>& model = body->model;
    const VibrationMode& mode = body->mode;
    SimulationSettings settings;
    settings.integrator = integrator;
    settings.dt = dt;
    settings.sleep = false;
    Simulator sim(model, settings);
    BodyState start = sim.saveState();
    for (std::size_t n = 0; n < model->nodeCount(); ++n)
        if (model->inverseMass[n] > 0.0)
            start.position[n] += body->amplitude * mode.shape[n];
    sim.restoreState(start);
    auto energy = [&] { return kineticEnergy(*model, sim.state()) + springEnergy(*model, sim.state()); };
    const double e0 = energy();
    std::vector<Vec3> displacement(model->nodeCount());
    auto projection = [&] {
        for (std::size_t n = 0; n < model->nodeCount(); ++n)
            displacement[n] = sim.state().position[n] - model->restPositions[n];
        return massInnerProduct(*model, mode.shape, displacement);
    };
    std::vector<double> samples{projection()};
    const long long steps = std::llround(seconds / dt);
    while (sim.stepCount() < steps) {
        if (sim.step(ExternalForces{}).refused)
            break;
        samples.resize(std::size_t(sim.stepCount()) + 1);  // a rollback of the guard steps its span again
        samples.back() = projection();
    }
    r.energyDrift = e0 > 0.0 ? (energy() - e0) / e0 : 0.0;
    if (samples.size() >= 4) {
        const FittedOscillation fit = fitOscillation(samples, dt);
        r.oscillates = fit.oscillates;
        r.keptPerPeriod = fit.amplitudePerPeriod;
        r.frequency = fit.frequencyHz;
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

std::string studyModelName(const LatticeShape& shape, BodyElement element) {
    return latticeShapeName(shape) + (element == BodyElement::Solid ? " solid" : "");
}

StudySetting sceneSetting(const Scene& scene) {
    const SceneObject& first = scene.objects.front();
    return {scene.world.simulation.integrator, scene.world.simulation.dt, first.lattice.shape(), first.material.element};
}

bool sameSetting(const StudySetting& a, const StudySetting& b) {
    return a.integrator == b.integrator && std::abs(a.dt - b.dt) <= 1e-12 * b.dt && a.lattice == b.lattice &&
           a.element == b.element;
}

Result<Scene> applySetting(const Scene& scene, const StudySetting& setting) {
    if (scene.objects.empty())
        return Status::error("the scene has no object");
    return withSetting(scene, setting);
}

double StudyResult::referenceUncertainty() const {
    return reference ? reference->uncertainty : std::numeric_limits<double>::infinity();
}

double StudyResult::certifiedFrom() const {
    return reference ? analysis::certifiedFrom(*reference) : std::numeric_limits<double>::infinity();
}

StudyResult runStudy(const Scene& scene, const ClipLibrary& library, const StudyOptions& options, std::ostream& log) {
    StudyResult result;
    result.error = options.error;
    if (scene.objects.empty()) {
        result.failure = "the scene has no object";
        return result;
    }
    auto clip = clipToPlay(scene, library, options.clip);
    if (!clip) {
        result.failure = clip.message();
        return result;
    }
    result.clip = clip.value();
    result.written = options.write ? options.written : std::string();
    for (const SceneObject& object : scene.objects)
        result.objects.push_back(object.name);
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
    const auto allKinds = integratorKinds();
    std::vector<IntegratorKind> kinds(allKinds.begin(), allKinds.end());
    // The solid element's part of the grid (StudyOptions::elements says why it is smaller).
    std::vector<LatticeShape> elementShapes;
    for (const LatticeShape& shape : shapes)
        if (shape.nodes[0] * shape.nodes[1] * shape.nodes[2] <= (options.quick ? kQuickStudyElementNodes : kStudyElementNodes))
            elementShapes.push_back(shape);
    std::vector<IntegratorKind> elementKinds = {IntegratorKind::ImplicitEuler};
    if (!options.lattices.empty())
        shapes = elementShapes = options.lattices;
    if (!options.integrators.empty()) {
        kinds = options.integrators;
        elementKinds.clear();
        std::copy_if(kinds.begin(), kinds.end(), std::back_inserter(elementKinds),
                     [](IntegratorKind k) { return integratorInfo(k).runsElement; });
    }
    if (!options.steps.empty())
        steps = options.steps;
    const std::vector<BodyElement> elements =
        options.elements.empty() ? std::vector<BodyElement>{BodyElement::Springs, BodyElement::Solid} : options.elements;
    std::vector<StudySetting> settings;
    for (const BodyElement element : elements) {
        const bool solid = element == BodyElement::Solid;
        for (const LatticeShape& shape : solid ? elementShapes : shapes)
            for (IntegratorKind kind : solid ? elementKinds : kinds)
                for (double dt : steps)
                    settings.push_back({kind, dt, shape, element});
    }
    const StudySetting current = sceneSetting(scene);
    if (options.includeCurrent &&
        std::none_of(settings.begin(), settings.end(), [&](const StudySetting& s) { return sameSetting(s, current); }))
        settings.push_back(current);

    // The truth: the converged solid, given by a study of the same scene and clip before, or made here on a thread
    // of its own beside the grid. It needs nothing the grid makes, and on two cores the grid's timed runs are not
    // slowed by it (docs/design/architecture.md, "The study grades against the converged solid"), so a first study
    // takes the longer of the two rather than their sum. Rows played before it is ready are graded once it is.
    std::mutex progressMutex;
    double referenceDone = options.given ? 1.0 : 0.0, gridDone = 0.0;
    std::atomic<bool> stopped = false;  // cancelled by the caller, or the reference failed: both threads stop
    auto report = [&](double& part, double fraction) {  // from either thread; false once stopped
        std::lock_guard lock(progressMutex);
        part = fraction;
        if (!stopped && options.progress && !options.progress(options.given ? gridDone : 0.5 * (referenceDone + gridDone))) {
            stopped = true;
            result.cancelled = true;
        }
        return !stopped.load();
    };
    std::ostringstream referenceLog;
    std::optional<Result<ConvergedReference>> made;
    std::atomic<bool> referenceReady = options.given != nullptr;
    std::jthread maker;
    if (!options.given) {
        maker = std::jthread([&] {
            ReferenceOptions ladder = options.reference;
            ladder.progress = [&](double fraction) { return report(referenceDone, fraction); };
            try {
                made.emplace(convergedReference(scene, library, clip.value(), ladder, referenceLog));
            } catch (const std::exception& e) {  // out of memory on a huge net: a failure, not a crash
                made.emplace(Status::error(std::string("the converged solid could not be made: ") + e.what()));
            }
            referenceReady = true;
        });
    }
    const std::vector<double> diagonals = meshDiagonals(scene);
    // The reference in hand: the baselines against it, logged, and a target checked. False when there is none (it
    // failed, was cancelled, or refuses the target), with `result` saying why.
    auto receiveReference = [&]() -> bool {
        if (maker.joinable())
            maker.join();
        if (options.given) {
            result.reference = options.given;
        } else {
            log << referenceLog.str();
            if (!*made) {
                result.failure = made->message();
                return false;
            }
            if ((*made)->cancelled) {  // the caller cancelled before it was done
                result.cancelled = true;
                return false;
            }
            result.reference = std::make_shared<const ConvergedReference>(std::move(made->value()));
        }
        const ClipMeshFrames& reference = result.reference->frames;
        auto rest = restFrames(scene, clip.value());
        if (!rest) {
            result.failure = rest.message();
            return false;
        }
        result.restError = worstDistance(objectDistances(rest.value(), reference, diagonals));
        for (std::size_t i = 0; i < diagonals.size(); ++i)
            result.motionAmplitude = std::max(result.motionAmplitude,
                                              trajectoryDistance(rest->positions[i], reference.positions[i], diagonals[i]).max);
        log << "clip '" << result.clip.name << "': " << result.clip.seconds() << " s from " << result.clip.startSeconds << " s at "
            << result.clip.fps << " fps, " << result.objects.size() << (result.objects.size() == 1 ? " object" : " objects")
            << "; the mesh moves up to " << result.motionAmplitude << " of its diagonal; doing nothing (the bodies at rest) scores "
            << result.restError << " (RMS, worst object)\n";
        if (options.target) {
            if (std::string refusal = refusalOfTarget(result, *options.target); !refusal.empty()) {
                char target[32];
                std::snprintf(target, sizeof target, "%g", *options.target);
                result.failure = std::string("target ") + target + " refused: " + refusal;
                return false;
            }
        }
        return true;
    };
    if (options.given && !receiveReference())
        return result;
    bool haveReference = options.given != nullptr;  // received: rows are graded as they are played

    const double freeSeconds = options.quick ? 2.0 : 3.0;  // several periods of the lowest lateral mode
    // Per lattice: converged in time (the reference of the integration error and of the frequency), and
    // its model error. Even exact integration trades amplitude between modes, so amplitude loss is
    // measured against the converged free vibration.
    struct LatticeRuns {
        std::string name;  ///< studyModelName()
        Scene scene;  ///< Every object on the lattice; the scene's own integrator and step.
        ClipRun converged;
        std::optional<double> modelError;  ///< Once graded against the reference.
        std::optional<FreeBody> freeBody;  ///< The first object undamped, and its lowest mode.
        FreeRun free;
        std::vector<double> solidModeError;
    };
    std::vector<std::shared_ptr<LatticeRuns>> lattices;
    std::vector<std::string> refused;
    std::ostringstream held;  // what the grid says before the reference's lines are in the log
    auto runsFor = [&](const LatticeShape& shape, BodyElement element) -> std::shared_ptr<LatticeRuns> {
        const std::string name = studyModelName(shape, element);
        for (auto& runs : lattices)
            if (runs->name == name)
                return runs;
        if (std::find(refused.begin(), refused.end(), name) != refused.end())
            return nullptr;
        auto moved = withSetting(scene, {scene.world.simulation.integrator, scene.world.simulation.dt, shape, element});
        if (!moved) {
            (haveReference ? static_cast<std::ostream&>(log) : held) << "  " << name << ": not measured: " << moved.message() << "\n";
            refused.push_back(name);
            return nullptr;
        }
        auto runs = std::make_shared<LatticeRuns>();
        runs->name = name;
        runs->scene = std::move(moved.value());
        runs->converged = runClip(convergedInTime(runs->scene, result.convergedDt), library, clip.value());
        const SceneObject& first = runs->scene.objects.front();
        runs->freeBody = freeBody(first);
        runs->free = runFree(runs->freeBody, IntegratorKind::Verlet, result.convergedDt, freeSeconds);
        if (auto compared = compareWithSolid(first.lattice, first.material))
            runs->solidModeError = compared->error;  // empty unless the solid converged
        lattices.push_back(runs);
        return runs;
    };

    // A row played, waiting for the reference to be graded (its clip's frames kept until then).
    struct Played {
        StudyRow row;
        ClipMeshFrames frames;
        std::shared_ptr<LatticeRuns> runs;
    };
    auto grade = [&](Played& played) {
        const ClipMeshFrames& reference = result.reference->frames;
        LatticeRuns& runs = *played.runs;
        if (!runs.modelError) {
            runs.modelError = worstDistance(objectDistances(runs.converged.frames, reference, diagonals));
            log << "  " << runs.name << ": model error " << *runs.modelError << " (RMS / diagonal)";
            if (!runs.solidModeError.empty())
                log << "; modes against the solid " << describeModeErrors(runs.solidModeError);
            log << "\n";
        }
        StudyRow& row = played.row;
        row.objectErrors = objectDistances(played.frames, reference, diagonals);
        row.finite = row.finite && std::all_of(row.objectErrors.begin(), row.objectErrors.end(),
                                               [](double e) { return std::isfinite(e); });
        row.rmsError = worstDistance(row.objectErrors);
        for (std::size_t o = 0; o < diagonals.size() && row.finite; ++o)
            row.maxError = std::max(row.maxError, trajectoryDistance(played.frames.positions[o], reference.positions[o], diagonals[o]).max);
        row.modelError = *runs.modelError;
        result.rows.push_back(row);
        char line[260];
        std::snprintf(line, sizeof line,
                      "  %-20s %-17s dt 1/%-4d  cost %9.2e s/s (+%3.0f%%)  error %8.2e (time %8.2e, model %8.2e)  "
                      "energy %+8.1e  loss/period %6.3f  freq %+7.3f%s\n",
                      row.resolution.c_str(), std::string(integratorName(row.integrator)).c_str(), int(std::lround(1 / row.dt)),
                      row.costPerSecond, 100.0 * row.costSpread, row.rmsError, row.timeError, row.modelError, row.energyDrift,
                      row.amplitudeLoss, row.frequencyError, row.current ? "  (the scene's own)" : "");
        log << line << std::flush;
    };
    std::vector<Played> waiting;
    // Takes the reference once it is ready (or, with `wait`, waits for it) and grades the rows that waited. False
    // when the study ends there (no reference).
    auto gradeWaiting = [&](bool wait) -> bool {
        if (!haveReference && (wait || referenceReady)) {
            if (!receiveReference()) {
                stopped = true;
                waiting.clear();
                return false;
            }
            haveReference = true;
            log << held.str();
        }
        if (haveReference) {
            for (Played& played : waiting)
                grade(played);
            waiting.clear();
        }
        return true;
    };

    for (std::size_t i = 0; i < settings.size(); ++i) {
        if (!report(gridDone, double(i) / double(settings.size())) || !gradeWaiting(false))
            break;
        const StudySetting& setting = settings[i];
        const auto runs = runsFor(setting.lattice, setting.element);
        if (!runs)
            continue;
        Played played;
        played.runs = runs;
        StudyRow& row = played.row;
        row.integrator = setting.integrator;
        row.dt = setting.dt;
        row.lattice = setting.lattice;
        row.element = setting.element;
        row.resolution = studyModelName(setting.lattice, setting.element);
        row.nodes = runs->scene.objects.front().lattice.nodeCount();
        row.current = sameSetting(setting, current);
        Scene run = runs->scene;
        run.world.simulation.integrator = setting.integrator;
        run.world.simulation.dt = setting.dt;
        ClipRun clipRun = runClip(run, library, clip.value(), options.write);
        if (!clipRun.writeFailure.empty()) {  // the scratch folder, not the setting: no row can be costed
            result.failure = "writing the clip as a bake does: " + clipRun.writeFailure;
            stopped = true;
            break;
        }
        // The cost the user pays for the clip: the fastest of the repeats (noise only ever adds time).
        double fastest = clipRun.seconds, slowest = clipRun.seconds;
        for (int r = 1; r < repeats; ++r) {
            const double seconds = runClip(run, library, clip.value(), options.write).seconds;
            fastest = std::min(fastest, seconds);
            slowest = std::max(slowest, seconds);
        }
        row.costPerSecond = fastest / result.clip.seconds();
        row.costSpread = fastest > 0.0 ? (slowest - fastest) / fastest : 0.0;
        row.finite = clipRun.finite;
        row.timeError = worstDistance(objectDistances(clipRun.frames, runs->converged.frames, diagonals));
        row.solidModeError = runs->solidModeError;
        const FreeRun free = runFree(runs->freeBody, setting.integrator, setting.dt, freeSeconds);
        row.energyDrift = free.energyDrift;
        const bool both = free.oscillates && runs->free.oscillates && runs->free.keptPerPeriod > 0.0;
        row.amplitudeLoss = both ? 1.0 - free.keptPerPeriod / runs->free.keptPerPeriod : 1.0;  // 1: no swing left
        row.frequencyError = both ? free.frequency / runs->free.frequency - 1.0
                                  : std::numeric_limits<double>::quiet_NaN();  // no oscillation seen
        played.frames = std::move(clipRun.frames);
        waiting.push_back(std::move(played));
        if (haveReference)
            gradeWaiting(false);
    }
    // The grid is done (or stopped): the reference's end, and the rows still waiting for it.
    if (!result.failure.empty() || !gradeWaiting(true))
        return result;
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
    const StudyRow* cheapest = nullptr;
    for (const StudyRow& r : result.rows) {
        if (r.finite && r.error(result.error) <= target && (!cheapest || r.costPerSecond < cheapest->costPerSecond))
            cheapest = &r;
    }
    if (!cheapest)
        return nullptr;
    // Within the cheapest one's own spread the costs cannot be told apart: the more accurate wins the tie.
    const StudyRow* best = cheapest;
    const double noise = cheapest->costPerSecond * (1.0 + cheapest->costSpread);
    for (const StudyRow& r : result.rows) {
        if (r.finite && r.error(result.error) <= target && r.costPerSecond <= noise &&
            r.error(result.error) < best->error(result.error))
            best = &r;
    }
    return best;
}

std::string refusalOfTarget(const StudyResult& result, double target) {
    char text[400];
    if (result.error == StudyError::Total && target >= result.restError) {
        std::snprintf(text, sizeof text,
                      "doing nothing at all (the bodies at rest) scores %.2e, within a target of %g: the target asks for no "
                      "motion (the clip moves up to %.2e of the diagonal)",
                      result.restError, target, result.motionAmplitude);
        return text;
    }
    if (result.error != StudyError::Integration && !(target >= result.certifiedFrom())) {
        std::snprintf(text, sizeof text,
                      "the converged solid is itself about %.2e of the diagonal from the limit, so a target below %.2e (ten "
                      "times that) cannot be certified against it",
                      result.referenceUncertainty(), result.certifiedFrom());
        return text;
    }
    return {};
}

Result<Remeasured> remeasure(const Scene& scene, const ClipLibrary& library, const StudyResult& study) {
    if (scene.objects.empty() || !study.reference)
        return Status::error("nothing to measure: no object or no reference");
    const std::vector<double> diagonals = meshDiagonals(scene);
    const ClipRun run = runClip(scene, library, study.clip);
    const ClipRun converged = runClip(convergedInTime(scene, study.convergedDt), library, study.clip);
    const ClipMeshFrames& reference = study.reference->frames;
    if (!run.failure.empty())
        return Status::error(run.failure);
    if (!run.finite || run.frames.frames != reference.frames || run.frames.positions.size() != reference.positions.size())
        return Status::error("the scene does not play the study's clip with the study's meshes");
    Remeasured r;
    r.total = worstDistance(objectDistances(run.frames, reference, diagonals));
    r.integration = worstDistance(objectDistances(run.frames, converged.frames, diagonals));
    r.model = worstDistance(objectDistances(converged.frames, reference, diagonals));
    if (!std::isfinite(r.total))
        return Status::error("the scene does not play the study's clip with the study's meshes");
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
    out << "integrator,dt_s,resolution,element,nodes,cost_s_per_s,cost_spread,rms_error,max_error,time_error,model_error,"
           "energy_drift,amplitude_loss_per_period,frequency_error,finite,pareto,current,solid_mode_error,object_errors\n";
    for (const StudyRow& r : result.rows) {
        out << integratorName(r.integrator) << ',' << r.dt << ',' << r.resolution << ','
            << (r.element == BodyElement::Solid ? "solid" : "springs") << ',' << r.nodes << ',' << r.costPerSecond
            << ',' << r.costSpread << ',' << r.rmsError << ',' << r.maxError << ',' << r.timeError << ',' << r.modelError << ','
            << r.energyDrift << ',' << r.amplitudeLoss << ',' << r.frequencyError << ',' << (r.finite ? 1 : 0) << ','
            << (r.pareto ? 1 : 0) << ',' << (r.current ? 1 : 0) << ',';
        if (!r.solidModeError.empty())  // the largest of the three; empty: no converged solid
            out << worstModeError(r.solidModeError);
        out << ',';
        for (std::size_t o = 0; o < r.objectErrors.size(); ++o)  // each object's total error, in scene order
            out << (o ? ";" : "") << r.objectErrors[o];
        out << '\n';
    }
    return out.str();
}

std::string studyMarkdown(const StudyResult& result, const std::string& command) {
    std::ostringstream out;
    auto row = [&](const StudyRow& r) {
        char line[320];
        std::snprintf(line, sizeof line, "| %s | 1/%d | %s | %.2e +%.0f%% | %.2e | %.2e | %.2e | %.2e | %+.1e | %.3f | %+.3f |%s\n",
                      std::string(integratorName(r.integrator)).c_str(), int(std::lround(1.0 / r.dt)), r.resolution.c_str(),
                      r.costPerSecond, 100.0 * r.costSpread, r.rmsError, r.timeError, r.modelError, r.maxError, r.energyDrift,
                      r.amplitudeLoss, r.frequencyError, r.pareto ? " ★ |" : " |");
        out << line;
    };
    const char* header = "| integrator | dt (s) | lattice | cost (s per clip s) | total error | integration error | "
                         "model error | max error | energy drift | amplitude lost / period | frequency error | Pareto |\n"
                         "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    const bool anySolid =
        std::any_of(result.rows.begin(), result.rows.end(), [](const StudyRow& r) { return r.element == BodyElement::Solid; });
    std::string objects;
    for (const std::string& name : result.objects)
        objects += (objects.empty() ? "" : ", ") + name;
    out << "# Speed against accuracy\n\nMade by `" << command << "`.\n\n"
        << "Every integrator × time step × lattice resolution"
        << (anySolid ? ", on springs and on the solid element (the lattices marked \"solid\"; by default implicit Euler "
                       "on lattices\nof up to " + std::to_string(kStudyElementNodes) + " nodes, as the element's cost suggests),\n"
                     : std::string(" "))
        << "plays the scene's clip '" << result.clip.name << "' ("
        << result.clip.seconds() << " s from " << result.clip.startSeconds << " s at " << result.clip.fps << " fps) as a bake exports it,\n"
        << "every object (" << objects << ") on the setting's lattice over its own box, with its drivers, anchors and\n"
        << "material carried to each resolution as the same continuum (density, Young's modulus and viscosity do not depend\n"
        << "on the lattice; anchors keep their extent in the material). Errors are RMS vertex distances over every frame,\n"
        << "relative to the mesh's bounding-box diagonal; the worst object's is shown.\n\n"
        << "- **cost**: wall seconds per second of clip for its "
        << (result.written.empty() ? std::string("physics and mesh deformation (one thread)")
                                   : "physics, mesh deformation (one thread) and writing " + result.written)
        << ",\n  the fastest of repeated runs, + how much slower the slowest was: what a bake of the clip pays.\n"
        << "- **total error**: the exported mesh against the converged solid (below). The Pareto front and picks use the\n"
        << "  **" << studyErrorName(result.error) << "** error.\n"
        << "- **integration error**: against this very lattice converged in time (Verlet at 1/"
        << int(std::lround(1.0 / result.convergedDt)) << " s): what the integrator and step alone cost.\n"
        << "- **model error**: this lattice converged in time against the converged solid: what the resolution and the\n"
        << "  element alone cost.\n"
        << "  It is the same for every integrator and step of a lattice.\n"
        << "- **what the numbers mean**: the mesh moves up to " << result.motionAmplitude
        << " of the diagonal in this clip, and doing nothing\n"
        << "  at all (the bodies at rest) scores " << result.restError << " RMS: an error is worth having only well below that.\n"
        << "- **free vibration** (first object, damping off, started in its lowest mode's shape, the motion projected on\n"
        << "  that mode and fitted as one damped oscillation): energy drift over the run; amplitude lost per period beyond\n"
        << "  what the same lattice converged in time keeps — implicit Euler's numerical damping shows here (1: no swing\n"
        << "  left); frequency error against that converged run.\n"
        << "- ★ marks the Pareto front: no other setting is both cheaper and more accurate.\n\n";
    if (result.reference) {
        const ConvergedReference& ref = *result.reference;
        out << "## The converged solid\n\nThe reference is the " << ref.description << ", the last rung of a ladder that "
            << "halves the step on the coarsest net, then refines the net. Each rung's change is the clip's RMS motion from "
            << "the rung before (relative to the diagonal; a rung's wall time is taken when it is made, and a reference read "
            << "from the cache keeps those of the study that made it):\n\n| rung | change | wall time |\n|---|---|---|\n";
        for (const ReferenceLevel& level : ref.levels) {
            char line[200];
            char change[32] = "—";
            if (std::isfinite(level.change))
                std::snprintf(change, sizeof change, "%.2e", level.change);
            std::snprintf(line, sizeof line, "| %s | %s | %.1f s |\n", level.what.c_str(), change, level.seconds);
            out << line;
        }
        out << "\nEstimated distance from the limit: " << ref.uncertainty << " (lattice " << ref.spaceUncertainty
            << (ref.spaceConverging ? ", the rest of the shrinking series of changes" : ", the last change: the changes do not shrink")
            << "; step " << ref.timeUncertainty << ", 4/3 of the change when the step is halved). A target below "
            << analysis::certifiedFrom(ref) << " (ten times it) cannot be certified.\n\n";
    }
    std::vector<const StudyRow*> sorted;
    for (const StudyRow& r : result.rows)
        sorted.push_back(&r);
    std::sort(sorted.begin(), sorted.end(), [](const StudyRow* a, const StudyRow* b) { return a->costPerSecond < b->costPerSecond; });
    out << "## Pareto front\n\n" << header;
    for (const StudyRow* r : sorted)
        if (r->pareto)
            row(*r);
    out << "\n## Model error by lattice\n\nModel error against the converged solid, and each lattice's three lowest modes "
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
