#pragma once
/// `softtouch-cli study`: the speed/accuracy trade measured on a scene. For every integrator × time
/// step × lattice resolution: cost per simulated second, error of the mesh against a converged
/// reference, and the integrator's character in free vibration (energy drift, amplitude lost per
/// period, frequency error). Reported as CSV, a markdown table with the Pareto front, and data for a plot.

#include "core/scene.h"

#include <ostream>
#include <string>
#include <vector>

namespace softtouch::bench {

/// What to run.
struct StudyOptions {
    bool quick = false;        ///< Fewer steps, resolutions and a shorter clip (for tests).
    double seconds = 2.0;      ///< Simulated time of each run, s (quick: 1).
};

/// One cell of the study.
struct StudyRow {
    IntegratorKind integrator = IntegratorKind::ImplicitEuler;
    double dt = 0.0;                   ///< Step, s.
    std::string resolution;            ///< e.g. "4x4x4 bezier".
    int nodes = 0;                     ///< Lattice nodes.
    double costPerSecond = 0.0;        ///< Wall seconds per simulated second (physics only).
    double rmsError = 0.0;             ///< RMS vertex error over all frames against the finest lattice
                                       ///< converged in time (time and resolution error together) / box diagonal.
    double maxError = 0.0;             ///< Largest vertex error over all frames, same reference / box diagonal.
    double timeError = 0.0;            ///< RMS error against this same lattice converged in time: what the
                                       ///< integrator and dt alone cost in accuracy / box diagonal.
    double energyDrift = 0.0;          ///< Free vibration, no damping: (E_end − E_0) / E_0.
    double amplitudeLoss = 0.0;        ///< Free vibration: fraction of amplitude lost per period.
    double frequencyError = 0.0;       ///< Free vibration: (f − f_ref) / f_ref, f_ref the same lattice converged.
    bool finite = true;                ///< No non-finite frame.
    bool pareto = false;               ///< No other row is both cheaper and more accurate.
};

/// The whole study.
struct StudyResult {
    std::vector<StudyRow> rows;
    std::string reference;             ///< How the reference was made.
    double referenceUncertainty = 0.0; ///< RMS change of the reference when its dt is halved (/ diagonal).
};

/// Runs the study on the first object of `scene` (its drivers, anchors and painted material, carried
/// to every resolution with resampleMaterial(..., keepContinuum = true)) in the scene's world, through the
/// same SceneSimulation a bake uses.
StudyResult runStudy(const Scene& scene, const StudyOptions& options, std::ostream& log);

/// The cheapest row whose RMS error is at most `target` (relative to the diagonal); nullptr if none.
const StudyRow* cheapestWithin(const StudyResult& result, double target);

/// CSV, one row per cell.
std::string studyCsv(const StudyResult& result);
/// Reads what studyCsv() wrote (docs/study.csv): the editor plots it. Errors name the line.
Result<StudyResult> parseStudyCsv(const std::string& text);
/// A markdown page: method, reference, the Pareto front, and every row sorted by cost.
std::string studyMarkdown(const StudyResult& result, const std::string& command);

}  // namespace softtouch::bench
