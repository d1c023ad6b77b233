#include "analysis/stability_grid.h"

#include "core/base/ranges.h"

#include "core/base/parallel.h"
#include "core/body/lattice_body.h"
#include "core/solver/simulator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>
#include <thread>
#include <tuple>

namespace softtouch::analysis {
namespace {

constexpr double kBoundFactors[] = {0.1, 1.0, 10.0};  // kDtLabels[0..2]; kDtLabels[3] is 1/24 s
constexpr double kFilmStep = 1.0 / 24.0;              ///< s, the coarsest step an animator would bake at.
constexpr double kMaxDt = ranges::kMaxDt;             ///< s, SimulationSettings' upper limit.
constexpr double kProjectMinDt = ranges::kMinDt;      ///< s, the project file's lower limit on dt.
constexpr double kEnergyEpsilon = 1e-12;              ///< J, absolute slack on the energy bound.
constexpr double kEnergyFactor = 2.0;                 ///< Energy may not exceed this times its start.
constexpr double kPerturbation = 0.01;                ///< m, 1% of the unit box, per component.
constexpr double kLargeDeformation = 0.05;            ///< m, 5% of the unit box: the undamped large-deformation runs.
const Vec3 kDragPoint(0.9, 0.5, 0.5);                 ///< (u,v,w) of the dragged material point.
const Vec3 kDragOffset(0.1, 0.1, 0.0);                ///< m, target relative to the point's rest position.

/// The values of each axis.
struct GridAxes {
    std::vector<double> stiffness; ///< N/m.
    std::vector<double> massRatio; ///< Heavy anchor ratio.
    std::vector<double> nodeMass;  ///< kg.
    std::vector<double> damping;   ///< N·s/m.
};

GridAxes gridAxes(bool quick) {
    if (quick)
        return {{1e-2, 1e2, 1e7}, {1.0, 1e6}, {1e-6, 1.0}, {0.0, 1e3}};
    return {{1e-2, 1.0, 1e2, 1e4, 1e7}, {1.0, 1e3, 1e6}, {1e-6, 1e-3, 1.0, 1e3}, {0.0, 1.0, 1e3}};
}

/// Deterministic noise in [-1, 1] (splitmix64 of the key): the same perturbation in every run.
double noise(std::uint64_t key) {
    std::uint64_t z = key + 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return double(z >> 11) * (2.0 / 9007199254740992.0) - 1.0;  // 53 bits -> [-1, 1)
}

/// One body of the grid (shared by its integrators and steps), its load and its start state.
struct CellSetup {
    double stiffness = 0.0;
    double massRatio = 1.0;
    double nodeMass = 0.0;
    double damping = 0.0;
    double perturbation = kPerturbation;
    bool dragReleased = false; ///< The drag lets go after half the run.
    std::shared_ptr<const BodyModel> model;
    ExternalForces forces;
    BodyState start;
    double stableStep = 0.0; ///< Explicit bound with safety 1, s.
};

/// 4x4x4 Bezier lattice over the unit box, u = 0 face pinned, u = 1 face Heavy (when the ratio is
/// above 1), one drag at (0.9, 0.5, 0.5) with the material's k and c, free nodes perturbed by up to
/// 1% of the box (5% for the large-deformation runs) so that every mode starts excited.
CellSetup makeSetup(const Lattice& lattice, double stiffness, double massRatio, double nodeMass, double damping,
                    double perturbation, bool dragReleased = false) {
    CellSetup setup;
    setup.perturbation = perturbation;
    setup.dragReleased = dragReleased;
    setup.stiffness = stiffness;
    setup.massRatio = massRatio;
    setup.nodeMass = nodeMass;
    setup.damping = damping;
    LatticeMaterial material = uniformMaterial(lattice, nodeMass, stiffness, damping);
    material.heavyAnchorRatio = massRatio;
    for (int k = 0; k < lattice.count(2); ++k)
        for (int j = 0; j < lattice.count(1); ++j) {
            material.anchor[std::size_t(lattice.index(0, j, k))] = AnchorMode::Pinned;
            if (massRatio > 1.0)
                material.anchor[std::size_t(lattice.index(lattice.count(0) - 1, j, k))] = AnchorMode::Heavy;
        }
    // The grid's values are all inside the material's ranges, so this cannot fail.
    setup.model = buildLatticeBody(lattice, material).value();

    DragSpring drag;
    drag.support = lattice.weights(kDragPoint);
    drag.target = lattice.box().toWorld(kDragPoint) + kDragOffset;
    drag.stiffness = stiffness;
    drag.damping = damping;
    setup.forces.drags.push_back(drag);

    setup.start = restState(*setup.model);
    for (std::size_t i = 0; i < setup.model->nodeCount(); ++i) {
        if (setup.model->inverseMass[i] == 0.0)
            continue;
        for (int c = 0; c < 3; ++c)
            setup.start.position[i][c] += perturbation * noise(3 * i + std::size_t(c));
    }

    SimulationSettings probe;
    probe.integrator = IntegratorKind::SymplecticEuler;
    probe.stabilitySafety = 1.0;
    setup.stableStep = Simulator(setup.model, probe).stableStep(setup.forces);
    return setup;
}

/// Kinetic + spring + drag energy, J. The drag target is fixed and every damping is >= 0, so the
/// exact solution never gains energy.
double totalEnergy(const BodyModel& model, const ExternalForces& forces, const BodyState& state) {
    double e = kineticEnergy(model, state) + springEnergy(model, state);
    for (const DragSpring& drag : forces.drags) {
        Vec3 point, pointVelocity;
        dragPointState(drag, state.position, state.velocity, point, pointVelocity);
        e += 0.5 * drag.stiffness * (drag.target - point).squaredNorm();
    }
    return e;
}

/// The energy a scheme conserves: E + (h/2) vᵀf(x) for the explicit schemes at substep h (f the
/// springs and the drag's pull at rest velocities; see Simulator), E itself for the others (h = 0).
double schemeEnergy(const BodyModel& model, const ExternalForces& forces, const BodyState& state, double h) {
    const double e = totalEnergy(model, forces, state);
    if (h <= 0.0)
        return e;
    const std::vector<Vec3> still(model.nodeCount(), Vec3::Zero());
    std::vector<Vec3> force(model.nodeCount());
    SpringScratch scratch;
    accumulateForces(model, forces, state.position, still, force, scratch);
    double power = 0.0;
    for (std::size_t i = 0; i < model.nodeCount(); ++i)
        power += model.inverseMass[i] > 0.0 ? state.velocity[i].dot(force[i]) : 0.0;
    return e + 0.5 * h * power;
}

/// Fixed material points whose deformed positions stand in for an exported frame.
std::vector<Vec3> samplePoints() {
    std::vector<Vec3> points;
    for (double w : {0.1, 0.9})
        for (double v : {0.1, 0.9})
            for (double u : {0.1, 0.9})
                points.emplace_back(u, v, w);
    return points;
}

/// A number for the tables: %g with `digits` significant digits, but whole numbers below 1e4 written
/// out (170, not 1.7e+02) and exponents without sign or padding (1e7, 1.5e-10).
std::string formatNumber(double value, int digits = 3) {
    if (!std::isfinite(value))
        return std::isnan(value) ? "nan" : "inf";
    char text[64];
    const double magnitude = std::abs(value);
    if (magnitude >= 1.0 && magnitude < 1e4)
        digits = std::max(digits, int(std::floor(std::log10(magnitude))) + 1);
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    std::string s = text;
    const std::size_t e = s.find('e');
    if (e == std::string::npos)
        return s;
    // 1e+07 -> 1e7, 1.5e-06 -> 1.5e-6
    std::string exponent = s.substr(e + 1);
    const bool negative = exponent[0] == '-';
    exponent.erase(0, exponent.find_first_not_of("+-0"));
    return s.substr(0, e) + "e" + (negative ? "-" : "") + exponent;
}

/// An axis value as written in the tables: 0.01, 1, 100, 1e4, 1e7, 1e-6, 0.001, 1000 ...
std::string axisValue(double value) { return formatNumber(value, 3); }

bool isExplicit(IntegratorKind kind) {
    return kind == IntegratorKind::SymplecticEuler || kind == IntegratorKind::Verlet;
}

/// Runs one cell and classifies it (see stability_grid.h).
StabilityCell runCell(const CellSetup& setup, const Lattice& lattice, IntegratorKind integrator, int dtIndex,
                      const StabilityGridOptions& options, int steps, int maxSubsteps) {
    StabilityCell cell;
    cell.integrator = integrator;
    cell.stiffness = setup.stiffness;
    cell.massRatio = setup.massRatio;
    cell.nodeMass = setup.nodeMass;
    cell.damping = setup.damping;
    cell.perturbation = setup.perturbation;
    cell.dragReleased = setup.dragReleased;
    cell.stableStep = setup.stableStep;
    cell.dtLabel = std::string(kDtLabels[dtIndex]);
    cell.steps = steps;
    cell.stabilitySafety = options.stabilitySafety;
    cell.substepLimit = maxSubsteps;
    std::vector<std::string> notes;
    if (dtIndex < 3) {
        cell.dt = kBoundFactors[dtIndex] * setup.stableStep;
        if (cell.dt > kMaxDt) {
            notes.push_back("dt clamped to 0.1 s (" + cell.dtLabel + " = " + formatNumber(cell.dt) + " s)");
            cell.dt = kMaxDt;
        }
    } else {
        cell.dt = kFilmStep;
    }

    SimulationSettings settings;
    settings.integrator = integrator;
    settings.dt = cell.dt;
    settings.maxSubsteps = maxSubsteps;
    settings.stabilitySafety = options.stabilitySafety;
    settings.sleep = false;  // every step must be computed and watched
    Simulator sim(setup.model, settings);
    sim.restoreState(setup.start);

    static const std::vector<Vec3> kSamples = samplePoints();
    const BodyModel& model = *setup.model;
    const double e0 = totalEnergy(model, setup.forces, setup.start);
    // Letting go removes the drag's potential from E and adds nothing, so 2 E0 stays a bound on the exact
    // motion; the step bound of the body alone is larger than with the drag, so no new substeps are due.
    const ExternalForces released;
    const int releaseStep = setup.dragReleased ? steps / 2 : steps;
    const double limit = kEnergyFactor * e0 + kEnergyEpsilon;
    double eMax = e0;
    bool unreportedGrowth = false;  // a step that said nothing ended above the energy limit
    std::vector<double> energies;   // per step, for the growth trend
    std::string firstProblem;
    int lastSubsteps = 0;
    for (int step = 0; step < steps; ++step) {
        const ExternalForces& forces = step < releaseStep ? setup.forces : released;
        const StepReport report = sim.step(forces);
        cell.maxSubsteps = std::max(cell.maxSubsteps, report.substeps);
        if (report.substeps > 0)
            lastSubsteps = report.substeps;  // the substep the last state was made with
        if (!report.problem.empty()) {
            if (report.rolledBack)
                ++cell.rolledBackSteps;
            else
                ++cell.refusedSteps;
            if (firstProblem.empty())
                firstProblem = report.problem;
        }
        // The simulator never keeps a non-finite state, but a finite one can still be huge enough for
        // the exported frame to overflow.
        bool finite = sim.state().isFinite();
        for (const Vec3& uvw : kSamples)
            finite = finite && isFinite(lattice.evaluate(uvw, sim.state().position));
        if (!finite) {
            cell.outputFinite = false;
            eMax = std::numeric_limits<double>::infinity();
            break;
        }
        const double e = totalEnergy(model, forces, sim.state());  // may overflow to inf
        energies.push_back(e);
        if (!(e <= eMax))
            eMax = e;
        if (report.problem.empty() && !(e <= limit))
            unreportedGrowth = true;
    }
    cell.energyGrowth = eMax / e0;
    if (cell.outputFinite) {
        const double h = isExplicit(integrator) && lastSubsteps > 0 ? cell.dt / lastSubsteps : 0.0;
        // A released run's end is measured without the drag it no longer has; its drift also holds the
        // drag's potential lost at release, so the drift figures leave it out.
        cell.energyDrift = schemeEnergy(model, setup.dragReleased ? released : setup.forces, sim.state(), h) / e0 - 1.0;
    } else {
        cell.energyDrift = std::numeric_limits<double>::infinity();
    }

    const bool reported = cell.refusedSteps + cell.rolledBackSteps > 0;
    const bool substepped = isExplicit(integrator) && cell.maxSubsteps > 1;
    // Still growing: the last third of the run peaks above 10x the peak before it. A numerical instability
    // grows exponentially (the explicit schemes' near-limit failures grow by ~1e16 per third of a run); an
    // overdamped body creeping towards a softened XPBD equilibrium rises slowly and levels off.
    const std::size_t third = energies.size() - energies.size() / 3;
    const double earlyPeak = energies.empty() ? e0 : *std::max_element(energies.begin(), energies.begin() + std::ptrdiff_t(third));
    const double latePeak = third < energies.size() ? *std::max_element(energies.begin() + std::ptrdiff_t(third), energies.end()) : earlyPeak;
    const bool growing = !(latePeak <= 10.0 * std::max(earlyPeak, e0)) || !(cell.energyGrowth <= 1e6);
    using Outcome = StabilityCell::Outcome;
    if (!cell.outputFinite || (unreportedGrowth && growing))
        cell.outcome = Outcome::Failed;
    else if (reported || substepped)
        cell.outcome = Outcome::Caught;
    else if (unreportedGrowth)
        cell.outcome = Outcome::Bounded;
    else
        cell.outcome = Outcome::Stable;

    if (!cell.outputFinite)
        notes.push_back("non-finite exported frame (a sample point overflowed)");
    if (cell.refusedSteps > 0)
        notes.push_back("refused " + std::to_string(cell.refusedSteps) + " of " + std::to_string(steps) + " steps");
    if (cell.rolledBackSteps > 0)
        notes.push_back("rolled back " + std::to_string(cell.rolledBackSteps) + " of " + std::to_string(steps) +
                        " steps");
    if (cell.outputFinite && cell.energyGrowth > kEnergyFactor) {
        const std::string growth = std::isfinite(cell.energyGrowth)
                                       ? "energy grew to " + formatNumber(cell.energyGrowth) + "x E0"
                                       : std::string("energy overflowed");
        notes.push_back(growth + (unreportedGrowth ? " in steps that reported nothing" : ""));
    }
    if (!firstProblem.empty())
        notes.push_back("\"" + firstProblem + "\"");
    for (std::size_t i = 0; i < notes.size(); ++i)
        cell.note += (i ? "; " : "") + notes[i];
    return cell;
}

char outcomeLetter(StabilityCell::Outcome outcome) {
    switch (outcome) {
    case StabilityCell::Outcome::Stable: return 'S';
    case StabilityCell::Outcome::Bounded: return 'B';
    case StabilityCell::Outcome::Caught: return 'C';
    case StabilityCell::Outcome::Failed: return 'F';
    }
    return '?';
}

/// Sorted distinct values of one field over the cells.
template <typename Field>
std::vector<double> distinct(const std::vector<StabilityCell>& cells, Field field) {
    std::vector<double> values;
    for (const StabilityCell& c : cells)
        values.push_back(field(c));
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
    return values;
}

}  // namespace

std::string_view outcomeName(StabilityCell::Outcome outcome) {
    switch (outcome) {
    case StabilityCell::Outcome::Stable: return "stable";
    case StabilityCell::Outcome::Bounded: return "bounded";
    case StabilityCell::Outcome::Caught: return "caught";
    case StabilityCell::Outcome::Failed: return "failed";
    }
    return "unknown";
}

OutcomeCounts countOutcomes(const std::vector<StabilityCell>& cells, IntegratorKind integrator) {
    OutcomeCounts counts;
    for (const StabilityCell& c : cells) {
        if (c.integrator != integrator)
            continue;
        switch (c.outcome) {
        case StabilityCell::Outcome::Stable: ++counts.stable; break;
        case StabilityCell::Outcome::Bounded: ++counts.bounded; break;
        case StabilityCell::Outcome::Caught: ++counts.caught; break;
        case StabilityCell::Outcome::Failed: ++counts.failed; break;
        }
    }
    return counts;
}

std::vector<StabilityCell> runStabilityGrid(const StabilityGridOptions& options) {
    const GridAxes axes = gridAxes(options.quick);
    const int steps = std::max(1, options.quick ? std::min(options.steps, 24) : options.steps);
    const int maxSubsteps = std::max(1, options.quick ? std::min(options.maxSubsteps, 2000) : options.maxSubsteps);
    const Lattice lattice = Lattice::create({LatticeKind::Bezier, {4, 4, 4}}, OrientedBox{}).value();

    std::vector<CellSetup> setups;
    for (double k : axes.stiffness)
        for (double r : axes.massRatio)
            for (double m : axes.nodeMass) {
                for (double c : axes.damping)
                    setups.push_back(makeSetup(lattice, k, r, m, c, kPerturbation));
                setups.push_back(makeSetup(lattice, k, r, m, 0.0, kLargeDeformation));  // undamped, large deformation
                setups.push_back(makeSetup(lattice, k, r, m, 0.0, kPerturbation, true));  // undamped, let go halfway
            }

    struct Job {
        std::size_t setup;
        IntegratorKind integrator;
        int dtIndex;
    };
    std::vector<Job> jobs;
    for (IntegratorKind integrator : integratorKinds())
        for (std::size_t s = 0; s < setups.size(); ++s)
            for (int d = 0; d < int(std::size(kDtLabels)); ++d)
                jobs.push_back({s, integrator, d});

    // Runs differ in cost by orders of magnitude (one substep to thousands), so workers pull the next
    // job from a shared counter instead of taking fixed ranges; each cell is written by one worker.
    std::vector<StabilityCell> cells(jobs.size());
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (std::size_t i = next++; i < jobs.size(); i = next++)
            cells[i] = runCell(setups[jobs[i].setup], lattice, jobs[i].integrator, jobs[i].dtIndex, options, steps,
                               maxSubsteps);
    };
    const int threads = std::min<int>(resolveThreadCount(options.threads), int(jobs.size()));
    {
        std::vector<std::jthread> workers;
        for (int t = 1; t < threads; ++t)
            workers.emplace_back(work);
        work();
    }
    return cells;
}

std::string stabilityMarkdown(const std::vector<StabilityCell>& cells, const std::string& command) {
    using Outcome = StabilityCell::Outcome;
    if (cells.empty())
        return "# Stability at the extremes\n\nNo runs.\n\nProduced by: `" + command + "`\n";
    const auto stiffness = distinct(cells, [](const StabilityCell& c) { return c.stiffness; });
    const auto ratios = distinct(cells, [](const StabilityCell& c) { return c.massRatio; });
    const auto masses = distinct(cells, [](const StabilityCell& c) { return c.nodeMass; });
    const auto dampings = distinct(cells, [](const StabilityCell& c) { return c.damping; });
    auto list = [](const std::vector<double>& values, const char* unit) {
        std::string s;
        for (std::size_t i = 0; i < values.size(); ++i)
            s += (i ? ", " : "") + axisValue(values[i]);
        return s + unit;
    };

    std::ostringstream md;
    md << "# Stability at the extremes\n\n"
       << "Generated by `" << command << "` (analysis/stability_grid.cpp): do not edit by hand,\n"
       << "run the command again.\n"
       << "Every integrator is run on one small dragged lattice over a grid of stiffness, anchor mass ratio, node\n"
       << "mass, damping and time step, and each run is classified by what came out and what the simulator's\n"
       << "guards did and said. " << cells.size() << " runs.\n\n";

    md << "## Method\n\n"
       << "- **Body**: a 4x4x4 Bezier lattice over the unit box (1 m), 468 springs, uniform per-node mass *m*,\n"
       << "  stiffness *k* and spring damping *c*. The u = 0 face (16 nodes) is Pinned. For a mass ratio *r* > 1\n"
       << "  the u = 1 face (16 nodes) is Heavy with `heavyAnchorRatio = r` (the paper's anchors); *r* = 1 means\n"
       << "  no heavy anchors. No gravity: sagging a 1e3 kg node on 1e-2 N/m springs is physics, not instability.\n"
       << "- **Load**: one drag spring on the material point (0.9, 0.5, 0.5), target 0.14 m away at rest point +\n"
       << "  (0.1, 0.1, 0) m, fixed. Its Ks and Kd are the cell's *k* and *c*, so the drag is exactly as extreme as\n"
       << "  the material (a drag of fixed 50 N/m would be negligible at 1e7 N/m and dominate at 1e-2 N/m).\n"
       << "  The undamped bodies are also run with the drag let go after half the run, the stretched body\n"
       << "  released as when an animator's drag ends (the hardest case for a tiny mass on soft springs at\n"
       << "  1/24 s).\n"
       << "- **Start**: every non-pinned node displaced by a fixed pseudo-random vector of up to 1 cm per\n"
       << "  component, zero velocity, so that every mode, the stiffest included, starts excited and an unstable\n"
       << "  scheme shows it within a few steps. The undamped bodies (*c* = 0) also start from a large\n"
       << "  deformation: up to 5 cm per component (5% of the body), which stretches springs by up to ~30%.\n"
       << "- **Axes**: *k* " << list(stiffness, " N/m") << "; *r* " << list(ratios, "") << "; *m* "
       << list(masses, " kg") << "; *c* " << list(dampings, " N·s/m") << ".\n"
       << "- **Time step**: 0.1x, 1x and 10x of the cell's explicit bound, and 1/24 s. The bound is\n"
       << "  `Simulator::stableStep` with `stabilitySafety = 1` for that body and drag: 2/ω (√(1+ζ²) − ζ) with\n"
       << "  ω² the largest eigenvalue of M⁻¹K (springs plus drag) and ζ its damping ratio (docs/design/lattice.md).\n"
       << "  Steps above 0.1 s (the settings' limit) are clamped to 0.1 s. Steps below the project file's\n"
       << "  1e-5 s limit are run as they are (the Simulator itself accepts any dt in (0, 0.1]), so \"0.1x bound\" always\n"
       << "  means a tenth of the bound.\n"
       << "- **Run**: the same body with every integrator and the simulator's guards as shipped\n"
       << "  (`stabilitySafety` " << formatNumber(cells.front().stabilitySafety) << ", XPBD "
       << SimulationSettings{}.xpbdSubsteps << " substeps), sleeping off,\n  `maxSubsteps` "
       << cells.front().substepLimit << " (beyond it a step is refused), " << cells.front().steps
       << " steps per run.\n"
       << "- **Exported frame**: after every step the state and the deformed positions of 8 material points\n"
       << "  ((u,v,w) in {0.1, 0.9}³, `Lattice::evaluate`) must be finite.\n"
       << "- **Energy**: E = kinetic + springs + ½ Ks |target − p|² of the drag. The target is fixed and all\n"
       << "  damping is ≥ 0, so the exact motion never gains energy.\n"
       << "- **Energy drift**: (Ẽ_end − E₀)/E₀ after the run, Ẽ the energy the scheme itself conserves: E for\n"
       << "  implicit Euler and XPBD, the modified energy E + (h/2) vᵀf for the explicit schemes (h their last\n"
       << "  substep; E swings by tens of percent around it near the bound, docs/design/lattice.md). Undamped, the\n"
       << "  exact motion keeps E₀, so the drift of an undamped run is all numerical. Runs the guard rolled back\n"
       << "  or refused are left out of the drift figures: their substep, and with it Ẽ, changed on the way;\n"
       << "  so are the released runs, whose E loses the drag's potential when it lets go.\n\n";

    md << "## Classes\n\n"
       << "- **S, stable**: every exported frame finite, no problem reported, explicit schemes not substepped,\n"
       << "  and E never above 2 E₀ + 1e-12 J.\n"
       << "- **C, caught**: the guard acted and it shows: a step was refused (it needed more than `maxSubsteps`)\n"
       << "  or rolled back (it became non-finite), both reported in `StepReport::problem`, or an explicit scheme\n"
       << "  was substepped below its bound (`StepReport::substeps` > 1); and every exported frame stayed finite\n"
       << "  and no step that reported nothing ended with E above 2 E₀. An explicit step above `stabilitySafety`\n"
       << "  times the bound is always substepped, so the 1x, 10x and most 1/24 s explicit runs are caught even\n"
       << "  when the motion is perfectly fine.\n"
       << "- **B, bounded**: finite and nothing reported, E above 2 E₀ but not growing (the last third of the run\n"
       << "  peaks no higher than 10x the rest): energy from nowhere that stopped growing, which no guard\n"
       << "  reported.\n"
       << "- **F, failed**: anything else: a non-finite exported frame, or E above 2 E₀ after a step that\n"
       << "  reported nothing and still growing at the end of the run (or beyond 10⁶ E₀), even when a later\n"
       << "  step is rolled back: the frames before it were already wrong.\n\n";

    md << "## Summary\n\n"
       << "| integrator | stable | bounded | caught | failed | runs | caught: substepped | caught: refused | caught: rolled back | energy drift, undamped (median, worst) |\n"
       << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    // Median |drift| and the largest in magnitude (signed) over the undamped runs with finite output.
    auto driftOf = [&](auto select) {
        std::vector<double> drifts;
        for (const StabilityCell& cell : cells)
            if (cell.damping == 0.0 && !cell.dragReleased && cell.outputFinite && cell.rolledBackSteps == 0 &&
                cell.refusedSteps == 0 && select(cell))
                drifts.push_back(cell.energyDrift);
        if (drifts.empty())
            return std::string("–");
        std::sort(drifts.begin(), drifts.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
        auto percent = [](double x) { return (x > 0.0 ? "+" : "") + formatNumber(100.0 * x, 2) + "%"; };
        return percent(drifts[drifts.size() / 2]) + ", " + percent(drifts.back());
    };
    OutcomeCounts all;
    int allSub = 0, allRef = 0, allRoll = 0;
    for (IntegratorKind kind : integratorKinds()) {
        const OutcomeCounts c = countOutcomes(cells, kind);
        int sub = 0, ref = 0, roll = 0;
        for (const StabilityCell& cell : cells) {
            if (cell.integrator != kind || cell.outcome != Outcome::Caught)
                continue;
            if (cell.refusedSteps > 0)
                ++ref;
            else if (cell.rolledBackSteps > 0)
                ++roll;
            else
                ++sub;
        }
        md << "| " << integratorName(kind) << " | " << c.stable << " | " << c.bounded << " | " << c.caught << " | " << c.failed << " | "
           << c.total() << " | " << sub << " | " << ref << " | " << roll << " | "
           << driftOf([&](const StabilityCell& cell) { return cell.integrator == kind; }) << " |\n";
        all.stable += c.stable;
        all.bounded += c.bounded;
        all.caught += c.caught;
        all.failed += c.failed;
        allSub += sub;
        allRef += ref;
        allRoll += roll;
    }
    md << "| **all** | " << all.stable << " | " << all.bounded << " | " << all.caught << " | " << all.failed << " | " << all.total()
       << " | " << allSub << " | " << allRef << " | " << allRoll << " | "
       << driftOf([](const StabilityCell&) { return true; }) << " |\n\n";

    md << "## Energy drift of the undamped runs\n\n"
       << "Median and largest (Ẽ_end − E₀)/E₀ over the undamped runs (*c* = 0) of each integrator, start deformation\n"
       << "and time step, after " << cells.front().steps << " steps, that nothing rolled back or refused (– where none). Implicit Euler loses energy by design (its\n"
       << "numerical damping); the explicit schemes keep their modified energy or are caught.\n\n"
       << "| integrator | start |";
    for (std::string_view label : kDtLabels)
        md << " " << label << " |";
    md << "\n|---|---|";
    for (std::size_t i = 0; i < std::size(kDtLabels); ++i)
        md << "---:|";
    md << "\n";
    for (IntegratorKind kind : integratorKinds())
        for (double perturbation : {kPerturbation, kLargeDeformation}) {
            md << "| " << integratorName(kind) << " | " << formatNumber(100.0 * perturbation) << " cm |";
            for (std::string_view label : kDtLabels)
                md << " " << driftOf([&](const StabilityCell& c) {
                    return c.integrator == kind && c.perturbation == perturbation && !c.dragReleased &&
                           c.dtLabel == label;
                }) << " |";
            md << "\n";
        }
    md << "\n";

    // The bound itself, without damping and anchors: how far apart the extremes are.
    md << "## The explicit bound\n\n"
       << "`stableStep` (safety 1) in seconds for *r* = 1; first figure *c* = 0, second *c* = "
       << axisValue(dampings.back()) << " N·s/m (heavy damping shrinks the explicit bound like 2/(damping rate)).\n\n"
       << "| *k* (N/m) \\ *m* (kg) |";
    for (double m : masses)
        md << " " << axisValue(m) << " |";
    md << "\n|---|";
    for (std::size_t i = 0; i < masses.size(); ++i)
        md << "---:|";
    md << "\n";
    auto boundOf = [&](double k, double m, double r, double c) {
        for (const StabilityCell& cell : cells)
            if (cell.stiffness == k && cell.nodeMass == m && cell.massRatio == r && cell.damping == c)
                return cell.stableStep;
        return std::numeric_limits<double>::quiet_NaN();
    };
    for (double k : stiffness) {
        md << "| " << axisValue(k) << " |";
        for (double m : masses)
            md << " " << formatNumber(boundOf(k, m, ratios.front(), dampings.front()), 2) << " / "
               << formatNumber(boundOf(k, m, ratios.front(), dampings.back()), 2) << " |";
        md << "\n";
    }
    md << "\n";

    md << "## Every run\n\n"
       << "One table per integrator: rows *k* × *m*, columns the time step. Each entry holds one letter per run\n"
       << "(S stable, B bounded, C caught, F failed) in groups of " << dampings.size() + 2
       << ", one group per mass ratio *r* = " << list(ratios, "") << "; inside a group, damping *c* = "
       << list(dampings, " N·s/m") << " from the 1 cm start, then *c* = 0 from the 5 cm start (large deformation),\n"
       << "then *c* = 0 with the drag let go halfway.\n\n";
    std::map<std::tuple<int, double, double, double, double, double, bool, std::string>, const StabilityCell*> index;
    for (const StabilityCell& c : cells)
        index[{int(c.integrator), c.stiffness, c.nodeMass, c.massRatio, c.damping, c.perturbation, c.dragReleased,
               c.dtLabel}] = &c;
    for (IntegratorKind kind : integratorKinds()) {
        md << "### " << integratorName(kind) << "\n\n| *k* (N/m) | *m* (kg) |";
        for (std::string_view label : kDtLabels)
            md << " " << label << " |";
        md << "\n|---:|---:|";
        for (std::size_t i = 0; i < std::size(kDtLabels); ++i)
            md << ":---:|";
        md << "\n";
        for (double k : stiffness)
            for (double m : masses) {
                md << "| " << axisValue(k) << " | " << axisValue(m) << " |";
                for (std::string_view label : kDtLabels) {
                    std::string entry;
                    for (double r : ratios) {
                        if (!entry.empty())
                            entry += ' ';
                        auto letter = [&](double c, double perturbation, bool released = false) {
                            const auto it =
                                index.find({int(kind), k, m, r, c, perturbation, released, std::string(label)});
                            return it == index.end() ? '-' : outcomeLetter(it->second->outcome);
                        };
                        for (double c : dampings)
                            entry += letter(c, kPerturbation);
                        entry += letter(0.0, kLargeDeformation);
                        entry += letter(0.0, kPerturbation, true);
                    }
                    md << " `" << entry << "` |";
                }
                md << "\n";
            }
        md << "\n";
    }

    md << "## Failed runs\n\n";
    std::vector<const StabilityCell*> failed;
    for (const StabilityCell& c : cells)
        if (c.outcome == Outcome::Failed)
            failed.push_back(&c);
    if (failed.empty()) {
        md << "None: no run produced a non-finite frame or gained energy without saying so.\n\n";
    } else {
        md << failed.size() << " runs. By time step:\n\n| integrator |";
        for (std::string_view label : kDtLabels)
            md << " " << label << " |";
        md << "\n|---|";
        for (std::size_t i = 0; i < std::size(kDtLabels); ++i)
            md << "---:|";
        md << "\n";
        for (IntegratorKind kind : integratorKinds()) {
            md << "| " << integratorName(kind) << " |";
            for (std::string_view label : kDtLabels) {
                auto here = [&](const StabilityCell* c) { return c->integrator == kind && c->dtLabel == label; };
                md << " " << std::count_if(failed.begin(), failed.end(), here) << " |";
            }
            md << "\n";
        }
        md << "\nEvery one. *h / bound*: the substep actually taken (dt / substeps) over the explicit bound; XPBD\n"
           << "always takes `xpbdSubsteps` substeps, whatever the bound. *rolled back*: steps the guard undid (in\n"
           << "a failed run, only after the energy had grown in steps that reported nothing). *E growth*: the largest\n"
           << "E / E₀ seen.\n\n"
           << "| integrator | *k* | *r* | *m* | *c* | step | dt (s) | substeps | h / bound | rolled back | E growth |\n"
           << "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|\n";
        for (const StabilityCell* c : failed) {
            const double substep = c->dt / std::max(1, c->maxSubsteps);
            md << "| " << integratorName(c->integrator) << " | " << axisValue(c->stiffness) << " | "
               << axisValue(c->massRatio) << " | " << axisValue(c->nodeMass) << " | " << axisValue(c->damping)
               << (c->dragReleased ? " (let go)" : c->perturbation > kPerturbation ? " (5 cm)" : "") << " | " << c->dtLabel << " | " << formatNumber(c->dt, 3) << " | " << c->maxSubsteps << " | "
               << formatNumber(substep / c->stableStep, 2) << " | " << c->rolledBackSteps << " | "
               << formatNumber(c->energyGrowth, 3) << " |\n";
        }
        md << "\n";
    }

    // Facts worth knowing that the letters hide.
    double worstStable = 1.0;
    int clamped = 0, belowProjectLimit = 0;
    for (const StabilityCell& c : cells) {
        if (c.outcome != Outcome::Failed)
            worstStable = std::max(worstStable, c.energyGrowth);
        if (c.note.find("clamped") != std::string::npos)
            ++clamped;
        if (c.dt < kProjectMinDt)
            ++belowProjectLimit;
    }
    md << "## Notes\n\n"
       << "- Largest energy growth among runs that did not fail: " << formatNumber(worstStable, 3) << "x E₀.\n"
       << "- " << clamped << " runs had their step clamped to 0.1 s; " << belowProjectLimit
       << " ran below the project file's 1e-5 s limit (reachable through the API only).\n"
       << "- Implicit Euler: ";
    const OutcomeCounts ie = countOutcomes(cells, IntegratorKind::ImplicitEuler);
    if (ie.stable == ie.total())
        md << "stable in all " << ie.total() << " runs, one linear solve per step whatever dt.\n";
    else
        md << ie.total() - ie.stable << " of " << ie.total() << " runs not stable (see the tables above).\n";
    md << "\nProduced by: `" << command << "`\n";
    return md.str();
}

}  // namespace softtouch::analysis
