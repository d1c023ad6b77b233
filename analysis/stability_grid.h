#pragma once
/// Stability at the extremes: one small dragged lattice run over a grid of stiffness, anchor mass
/// ratio, node mass, damping and time step, for every integrator, and each run classified by what
/// the simulator's guards did. `softtouch-cli stability` writes the result to docs/measurements/stability.md;
/// tests/bench/test_stability_grid.cpp asserts on the quick grid.
///
///   Stable  every exported frame finite, no problem reported, explicit schemes not substepped, and
///           the energy never above 2x its start (+ 1e-12 J)
///   Caught  the guard acted and it shows, every exported frame finite, and no step that reported
///           nothing ended above the energy limit: a step was refused or rolled back
///           (StepReport::problem), or an explicit scheme was substepped (StepReport::substeps > 1)
///   Bounded finite, nothing reported, energy above 2x its start but not growing (the last third of the
///           run peaks no higher than 10x the rest): energy from nowhere that stopped growing, unreported
///   Failed  anything else: a non-finite exported frame, or energy growth in a step that said nothing
///           that is still growing at the end of the run (or beyond 1e6x its start)
#include "core/solver/integrator.h"
#include "core/solver/simulator.h"

#include <string>
#include <string_view>
#include <vector>

namespace softtouch::analysis {

/// One run of the grid and how it ended.
struct StabilityCell {
    /// How a run ended (see the file comment).
    enum class Outcome { Stable, Bounded, Caught, Failed };

    IntegratorKind integrator = IntegratorKind::ImplicitEuler; ///< Scheme.
    double stiffness = 0.0;     ///< Per-node stiffness, N/m; also the drag's Ks. Grid: [1e-2, 1e7].
    double massRatio = 1.0;     ///< heavyAnchorRatio of the u = 1 face (1: no heavy anchors). Grid: [1, 1e6].
    double nodeMass = 0.0;      ///< Per-node mass, kg. Grid: [1e-6, 1e3].
    double damping = 0.0;       ///< Per-node spring damping, N·s/m; also the drag's Kd. Grid: [0, 1e3].
    double perturbation = 0.01; ///< Largest start displacement of a node per component, m: 0.01, or 0.05
                                ///< (5% of the body: large deformation, undamped runs only).
    bool dragReleased = false;  ///< The drag lets go after half the run (undamped runs from the 1 cm start
                                ///< only): the stretched body is released, as an animator's drag ends.
    double stableStep = 0.0;    ///< The explicit bound of this body and drag (Simulator::stableStep with
                                ///< stabilitySafety 1), seconds; the "x bound" steps are multiples of it.
    double dt = 0.0;            ///< The step actually run, seconds, (0, 0.1].
    int steps = 0;              ///< Steps run (StabilityGridOptions::steps).
    double stabilitySafety = 0.9; ///< SimulationSettings::stabilitySafety of the run.
    int substepLimit = 0;       ///< SimulationSettings::maxSubsteps of the run.
    std::string dtLabel;        ///< "0.1x bound", "1x bound", "10x bound" or "1/24 s".
    Outcome outcome = Outcome::Failed; ///< Classification, filled by runStabilityGrid().
    bool outputFinite = true;   ///< Every step's state and sampled deformed points were finite.
    int maxSubsteps = 0;        ///< Largest StepReport::substeps over the run (0: every step refused).
    int refusedSteps = 0;       ///< Steps refused for needing more than SimulationSettings::maxSubsteps.
    int rolledBackSteps = 0;    ///< Steps rolled back because the state became non-finite.
    double energyGrowth = 1.0;  ///< max E / E0 over the run (E: kinetic + springs + drag), >= 1.
    double energyDrift = 0.0;   ///< (Ẽ_end − E0) / E0, Ẽ the energy the scheme conserves: E for implicit Euler
                                ///< and XPBD, E + (h/2) vᵀf for the explicit schemes (h their last substep).
                                ///< Undamped runs: pure numerical drift. Infinite if the output was not finite.
    std::string note;           ///< Empty, or what is unusual (clamped dt, first problem reported).
};

/// What to run.
struct StabilityGridOptions {
    bool quick = false;      ///< Fewer values per axis (the test's grid; seconds, not minutes).
    int steps = 48;          ///< Steps per run. Range [1, 100000]. Quick mode uses at most 24.
    int maxSubsteps = 20000; ///< SimulationSettings::maxSubsteps of every run: beyond it a step is refused
                             ///< (a refusal is Caught). Quick mode uses at most 2000. Range [1, 1e9].
    double stabilitySafety = SimulationSettings{}.stabilitySafety; ///< Of every run (the shipped default).
                                  ///< Range (0, 1]. The "x bound" steps always use the bound at safety 1.
    int threads = 0;         ///< Runs in parallel (each run single-threaded, results independent of it);
                             ///< <= 0: every hardware thread.
};

/// Cells per integrator and outcome.
struct OutcomeCounts {
    int stable = 0;   ///< Outcome::Stable.
    int bounded = 0;  ///< Outcome::Bounded.
    int caught = 0;   ///< Outcome::Caught.
    int failed = 0;   ///< Outcome::Failed.
    int total() const { return stable + bounded + caught + failed; }
};

/// The four dt labels, in grid order.
inline constexpr std::string_view kDtLabels[] = {"0.1x bound", "1x bound", "10x bound", "1/24 s"};

/// Runs the grid: every integrator for every combination of the axes (see stabilityMarkdown() for the
/// method). Deterministic: the same options give the same cells, whatever the thread count.
std::vector<StabilityCell> runStabilityGrid(const StabilityGridOptions& options);

/// "stable", "bounded", "caught" or "failed".
std::string_view outcomeName(StabilityCell::Outcome outcome);

/// Counts of the cells of one integrator.
OutcomeCounts countOutcomes(const std::vector<StabilityCell>& cells, IntegratorKind integrator);

/// The docs page (docs/measurements/stability.md): method, what each class means, counts per integrator, one
/// compact table per integrator, every Failed cell, and `command`, the command that produced it.
std::string stabilityMarkdown(const std::vector<StabilityCell>& cells, const std::string& command);

}  // namespace softtouch::analysis
