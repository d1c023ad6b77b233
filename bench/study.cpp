#include "bench/study.h"

#include "bench/timer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace softtouch::bench {
namespace {

struct Resolution {
    LatticeShape shape;
    std::string name;
};

std::string shapeName(const LatticeShape& s) {
    return std::to_string(s.nodes[0]) + "x" + std::to_string(s.nodes[1]) + "x" + std::to_string(s.nodes[2]) +
           (s.kind == LatticeKind::Bezier ? " bezier" : " bspline");
}

/// The object rebuilt on another lattice over the same box, material carried over as a continuum.
SceneObject onLattice(const SceneObject& source, const LatticeShape& shape) {
    SceneObject o = source;
    o.lattice = Lattice::create(shape, source.lattice.box()).value();
    o.material = resampleMaterial(source.lattice, source.material, o.lattice, true);
    return o;
}

/// Mesh frames at `fps` over `seconds` of driven simulation, and the wall time of the physics.
struct DrivenRun {
    std::vector<std::vector<Vec3f>> frames;
    double physicsSeconds = 0.0;
    bool finite = true;
};

/// Runs the object through the same SceneSimulation a bake uses (its drivers, the scene's world), with
/// the study's integrator and step.
DrivenRun runDriven(const SceneObject& object, const WorldSettings& world, IntegratorKind integrator, double dt,
                    double seconds, double fps) {
    Scene scene;
    scene.objects = {object};
    scene.world = world;
    scene.world.simulation.integrator = integrator;
    scene.world.simulation.dt = dt;
    scene.world.simulation.sleep = false;
    scene.world.simulation.xpbdSubsteps = 8;
    auto sim = SceneSimulation::create(scene);
    DrivenRun run;
    if (!sim) {
        run.finite = false;
        return run;
    }
    const int frames = int(std::lround(seconds * fps));
    for (int f = 1; f <= frames; ++f) {
        Stopwatch watch;
        sim->advanceTo(double(f) / fps);
        run.physicsSeconds += watch.seconds();
        std::vector<Vec3f> positions(object.mesh.positions.size());
        sim->evaluate(0, positions, {}, 0);
        for (const Vec3f& p : positions)
            run.finite = run.finite && p.allFinite();
        run.frames.push_back(std::move(positions));
    }
    return run;
}

/// RMS and max distance between two frame sequences.
std::pair<double, double> frameError(const std::vector<std::vector<Vec3f>>& a, const std::vector<std::vector<Vec3f>>& b) {
    double sum = 0.0, worst = 0.0;
    std::size_t count = 0;
    for (std::size_t f = 0; f < std::min(a.size(), b.size()); ++f) {
        for (std::size_t v = 0; v < a[f].size(); ++v) {
            const double d = double((a[f][v] - b[f][v]).norm());
            sum += d * d;
            worst = std::max(worst, d);
            ++count;
        }
    }
    return {std::sqrt(sum / double(std::max<std::size_t>(1, count))), worst};
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

StudyResult runStudy(const Scene& scene, const StudyOptions& options, std::ostream& log) {
    const SceneObject& source = scene.objects.front();
    const double seconds = options.quick ? std::min(1.0, options.seconds) : options.seconds;
    const double fps = 24.0;
    std::vector<double> steps = {1.0 / 1000, 1.0 / 480, 1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 24};
    std::vector<Resolution> resolutions = {{{LatticeKind::Bezier, {2, 2, 2}}, ""}, {{LatticeKind::Bezier, {3, 3, 3}}, ""},
                                           {{LatticeKind::Bezier, {4, 4, 4}}, ""}, {{LatticeKind::BSpline, {6, 6, 6}}, ""},
                                           {{LatticeKind::BSpline, {8, 8, 8}}, ""}};
    if (options.quick) {
        steps = {1.0 / 240, 1.0 / 60, 1.0 / 24};
        resolutions = {{{LatticeKind::Bezier, {3, 3, 3}}, ""}, {{LatticeKind::Bezier, {4, 4, 4}}, ""},
                       {{LatticeKind::BSpline, {6, 6, 6}}, ""}};
    }
    for (Resolution& r : resolutions)
        r.name = shapeName(r.shape);

    // Reference: the finest lattice, central differences (second order) at a tiny step; halving the
    // step again says how converged it is.
    const LatticeShape referenceShape{LatticeKind::BSpline, options.quick ? std::array<int, 3>{8, 8, 8} : std::array<int, 3>{10, 10, 10}};
    const double referenceDt = options.quick ? 1.0 / 4000 : 1.0 / 8000;
    const SceneObject referenceObject = onLattice(source, referenceShape);
    const DrivenRun reference = runDriven(referenceObject, scene.world, IntegratorKind::Verlet, referenceDt, seconds, fps);
    const DrivenRun finer = runDriven(referenceObject, scene.world, IntegratorKind::Verlet, referenceDt / 2, seconds, fps);
    const double diagonal = source.lattice.box().diagonal();
    StudyResult result;
    result.referenceUncertainty = frameError(reference.frames, finer.frames).first / diagonal;
    result.reference = shapeName(referenceShape) + ", verlet, dt = 1/" + std::to_string(int(std::lround(1.0 / referenceDt))) + " s";
    log << "reference: " << result.reference << " (halving its dt changes it by " << result.referenceUncertainty
        << " of the diagonal, RMS)\n";

    constexpr IntegratorKind kinds[] = {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet,
                                        IntegratorKind::ImplicitEuler, IntegratorKind::Xpbd};
    const double freeSeconds = options.quick ? 2.0 : 3.0;  // several periods of the lowest lateral mode
    for (const Resolution& res : resolutions) {
        const SceneObject object = onLattice(source, res.shape);
        // This lattice converged in time: the reference for the time error and the frequency.
        const DrivenRun converged = runDriven(object, scene.world, IntegratorKind::Verlet, referenceDt, seconds, fps);
        // Even exact integration trades amplitude between modes, so amplitude loss is measured against it.
        const FreeRun referenceFree = runFree(object, IntegratorKind::Verlet, referenceDt, freeSeconds);
        const double referenceFrequency = referenceFree.frequency;
        for (IntegratorKind kind : kinds) {
            for (double dt : steps) {
                StudyRow row;
                row.integrator = kind;
                row.dt = dt;
                row.resolution = res.name;
                row.nodes = object.lattice.nodeCount();
                const DrivenRun run = runDriven(object, scene.world, kind, dt, seconds, fps);
                row.costPerSecond = run.physicsSeconds / seconds;
                row.finite = run.finite;
                const auto [rms, worst] = frameError(run.frames, reference.frames);
                row.rmsError = rms / diagonal;
                row.maxError = worst / diagonal;
                row.timeError = frameError(run.frames, converged.frames).first / diagonal;
                const FreeRun free = runFree(object, kind, dt, freeSeconds);
                row.energyDrift = free.energyDrift;
                if (free.periods > 0.0 && referenceFree.amplitudeRatio > 0.0)
                    row.amplitudeLoss = 1.0 - std::pow(std::max(0.0, free.amplitudeRatio / referenceFree.amplitudeRatio), 1.0 / free.periods);
                row.frequencyError = referenceFrequency > 0.0 && free.frequency > 0.0
                                         ? free.frequency / referenceFrequency - 1.0
                                         : std::numeric_limits<double>::quiet_NaN();  // no oscillation seen
                result.rows.push_back(row);
                char line[200];
                std::snprintf(line, sizeof line,
                              "  %-14s %-17s dt 1/%-4d  cost %9.2e s/s  error %8.2e (time %8.2e)  energy %+8.1e  "
                              "loss/period %6.3f  freq %+7.3f\n",
                              res.name.c_str(), std::string(integratorName(kind)).c_str(), int(std::lround(1 / dt)),
                              row.costPerSecond, row.rmsError, row.timeError, row.energyDrift, row.amplitudeLoss,
                              row.frequencyError);
                log << line << std::flush;
            }
        }
    }
    for (StudyRow& a : result.rows) {
        a.pareto = a.finite && std::none_of(result.rows.begin(), result.rows.end(), [&](const StudyRow& b) {
                       return &b != &a && b.finite && b.costPerSecond <= a.costPerSecond && b.rmsError <= a.rmsError &&
                              (b.costPerSecond < a.costPerSecond || b.rmsError < a.rmsError);
                   });
    }
    return result;
}

const StudyRow* cheapestWithin(const StudyResult& result, double target) {
    const StudyRow* best = nullptr;
    for (const StudyRow& r : result.rows) {
        if (r.finite && r.rmsError <= target && (!best || r.costPerSecond < best->costPerSecond))
            best = &r;
    }
    return best;
}

std::string studyCsv(const StudyResult& result) {
    std::ostringstream out;
    out << "integrator,dt_s,resolution,nodes,cost_s_per_s,rms_error,max_error,time_error,energy_drift,"
           "amplitude_loss_per_period,frequency_error,finite,pareto\n";
    for (const StudyRow& r : result.rows)
        out << integratorName(r.integrator) << ',' << r.dt << ',' << r.resolution << ',' << r.nodes << ',' << r.costPerSecond
            << ',' << r.rmsError << ',' << r.maxError << ',' << r.timeError << ',' << r.energyDrift << ',' << r.amplitudeLoss << ','
            << r.frequencyError << ',' << (r.finite ? 1 : 0) << ',' << (r.pareto ? 1 : 0) << '\n';
    return out.str();
}

Result<StudyResult> parseStudyCsv(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    StudyResult result;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        if (number == 1 || line.empty())
            continue;  // the header
        std::vector<std::string> f;
        std::stringstream cells(line);
        for (std::string cell; std::getline(cells, cell, ',');)
            f.push_back(cell);
        const auto kind = f.size() == 13 ? parseIntegratorKind(f[0]) : std::nullopt;
        if (!kind)
            return Status::error("line " + std::to_string(number) + ": expected 13 fields starting with an integrator name");
        StudyRow r;
        r.integrator = *kind;
        try {
            r.dt = std::stod(f[1]);
            r.resolution = f[2];
            r.nodes = std::stoi(f[3]);
            r.costPerSecond = std::stod(f[4]);
            r.rmsError = std::stod(f[5]);
            r.maxError = std::stod(f[6]);
            r.timeError = std::stod(f[7]);
            r.energyDrift = std::stod(f[8]);
            r.amplitudeLoss = std::stod(f[9]);
            r.frequencyError = std::stod(f[10]);
            r.finite = f[11] == "1";
            r.pareto = f[12] == "1";
        } catch (const std::exception&) {
            return Status::error("line " + std::to_string(number) + ": a field is not a number");
        }
        result.rows.push_back(std::move(r));
    }
    if (result.rows.empty())
        return Status::error("no study rows");
    return result;
}

std::string studyMarkdown(const StudyResult& result, const std::string& command) {
    std::ostringstream out;
    auto row = [&](const StudyRow& r) {
        char line[300];
        std::snprintf(line, sizeof line, "| %s | 1/%d | %s | %.2e | %.2e | %.2e | %.2e | %+.1e | %.3f | %+.3f |%s\n",
                      std::string(integratorName(r.integrator)).c_str(), int(std::lround(1.0 / r.dt)), r.resolution.c_str(),
                      r.costPerSecond, r.rmsError, r.maxError, r.timeError, r.energyDrift, r.amplitudeLoss, r.frequencyError,
                      r.pareto ? " ★ |" : " |");
        out << line;
    };
    const char* header = "| integrator | dt (s) | lattice | cost (s per simulated s) | RMS error | max error | time error | "
                         "energy drift | amplitude lost / period | frequency error | Pareto |\n"
                         "|---|---|---|---|---|---|---|---|---|---|---|\n";
    out << "# Speed against accuracy\n\nMade by `" << command << "`.\n\n"
        << "Every integrator × time step × lattice resolution simulates the same scene (its drivers, anchors and material,\n"
        << "carried to each resolution as the same continuum: node mass with volume, spring stiffness with spacing).\n\n"
        << "- **cost**: wall seconds of physics per simulated second (one thread; mesh evaluation excluded).\n"
        << "- **error**: mesh vertex distance to the reference at every frame (24 fps), RMS and max, relative to the box diagonal.\n"
        << "  The reference is the finest lattice converged in time, so this is time and resolution error together. Lattices of\n"
        << "  different resolution are different models of the object (the springs join control points, not material points),\n"
        << "  so the resolution part does not vanish as the lattice is refined the way a finite-element error would.\n"
        << "- **time error**: the same, against this very lattice converged in time (Verlet at the reference step): what the\n"
        << "  integrator and dt alone cost.\n"
        << "- **reference**: " << result.reference << "; halving its step changes it by " << result.referenceUncertainty
        << " (RMS, relative): errors below that are noise.\n"
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
    out << "\n## Every setting, cheapest first\n\n" << header;
    for (const StudyRow* r : sorted)
        row(*r);
    return out.str();
}

}  // namespace softtouch::bench
