#pragma once
/// `softtouch-cli study`: the speed/accuracy trade measured on a scene. For every integrator × time
/// step × lattice resolution: cost per simulated second (median of repeats), and two errors of the mesh
/// kept apart: integration error (this lattice against itself converged in time) and model error (this
/// lattice converged in time against the finest lattice, same material), beside the clip's own motion and
/// the do-nothing baseline. Also the integrator's character in free vibration (energy drift, amplitude
/// lost per period, frequency error). Reported as CSV, a markdown table with the Pareto front, and data
/// for a plot; a pick can be written into a project and re-measured as written.

#include "core/scene.h"

#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace softtouch::analysis {

/// Which error a target, the Pareto front and a pick use.
enum class StudyError {
    Total,        ///< Against the finest lattice converged in time: integration and model error together.
    Integration,  ///< Against this same lattice converged in time: what the integrator and step cost.
    Model,        ///< This lattice converged in time against the finest: what the resolution costs.
};
std::string_view studyErrorName(StudyError kind);              ///< "total", "integration", "model".
std::optional<StudyError> parseStudyError(std::string_view name);

/// The settings a study row measures.
struct StudySetting {
    IntegratorKind integrator = IntegratorKind::Verlet;
    double dt = 1.0 / 240;     ///< Step, s.
    LatticeShape lattice;      ///< Kind and nodes per axis, over the object's box.
};

/// The scene's own setting: the world's integrator and step, the first object's lattice (it must have one).
StudySetting sceneSetting(const Scene& scene);
/// Whether two settings are the same (the steps equal within rounding): how a row is found to be the scene's own.
bool sameSetting(const StudySetting& a, const StudySetting& b);

/// What to run.
struct StudyOptions {
    bool quick = false;        ///< Fewer steps and resolutions (for tests and the editor); the same clip.
    /// Simulated time of each run, s; 0: the scene's clip (world.frames / world.fps), as a bake runs it.
    double seconds = 0.0;
    StudyError error = StudyError::Total;
    int repeats = 5;           ///< Timed runs per setting; the cost is their median. [1, 100].
    /// The grid; empty: the default (quick) grid. Lattices are carried over the object's box.
    std::vector<LatticeShape> lattices;
    std::vector<IntegratorKind> integrators;
    std::vector<double> steps;
    /// Also measure the scene's own setting (integrator, step and lattice of its first object).
    bool includeCurrent = true;
    /// Called between runs with the fraction done; returning false cancels (the result then says so).
    std::function<bool(double)> progress;
};

/// One cell of the study.
struct StudyRow {
    IntegratorKind integrator = IntegratorKind::ImplicitEuler;
    double dt = 0.0;                   ///< Step, s.
    LatticeShape lattice;              ///< Kind and nodes per axis.
    std::string resolution;            ///< latticeShapeName(lattice), e.g. "4x4x4 bezier".
    int nodes = 0;                     ///< Lattice nodes.
    double costPerSecond = 0.0;        ///< Wall seconds per simulated second (physics only), median of the repeats.
    double costSpread = 0.0;           ///< (slowest − fastest) / median of the repeats.
    double rmsError = 0.0;             ///< Total: RMS vertex error over all frames against the reference / box diagonal.
    double maxError = 0.0;             ///< Largest vertex error over all frames, same reference / box diagonal.
    double timeError = 0.0;            ///< Integration: RMS error against this same lattice converged in time / diagonal.
    double modelError = 0.0;           ///< Model: this lattice converged in time against the reference (RMS / diagonal).
    double energyDrift = 0.0;          ///< Free vibration, no damping: (E_end − E_0) / E_0.
    double amplitudeLoss = 0.0;        ///< Free vibration: fraction of amplitude lost per period.
    double frequencyError = 0.0;       ///< Free vibration: (f − f_ref) / f_ref, f_ref the same lattice converged.
    /// The lattice's three lowest modes against the converged solid of its material (core/solid_modes.h):
    /// f_lattice / f_solid − 1 each. Empty when that solid does not converge (point anchors) or cannot be
    /// analysed. Like the model error it belongs to the lattice, but it needs no finest lattice.
    std::vector<double> solidModeError;
    bool finite = true;                ///< No non-finite frame.
    bool pareto = false;               ///< No other row is both cheaper and more accurate (in the study's error).
    bool current = false;              ///< The scene's own setting.

    double error(StudyError kind) const;
    StudySetting setting() const { return {integrator, dt, lattice}; }
};

/// The whole study.
struct StudyResult {
    std::vector<StudyRow> rows;
    StudyError error = StudyError::Total;  ///< The error the front and picks use.
    std::string reference;             ///< How the reference was made.
    double referenceUncertainty = 0.0; ///< RMS change of the reference when its dt is halved (/ diagonal).
    double restError = 0.0;            ///< The do-nothing baseline: the rest pose against the reference (RMS / diagonal).
    double motionAmplitude = 0.0;      ///< Largest vertex displacement of the reference from rest / diagonal.
    double seconds = 0.0;              ///< Simulated time of each run, s.
    double fps = 24.0;                 ///< Frames compared per second.
    bool cancelled = false;            ///< The progress callback stopped it; rows are those measured so far.
    /// The reference's mesh positions, every frame one after another (kept to re-measure a pick as written).
    std::shared_ptr<const std::vector<Vec3f>> referenceFrames;
    double referenceDt = 0.0;          ///< Step of the converged runs, s.
};

/// "4x4x4 bezier": how the study names a lattice shape.
std::string latticeShapeName(const LatticeShape& shape);

/// Runs the study on the first object of `scene` (its drivers, anchors and painted material, carried
/// to every resolution with resampleMaterial(..., keepContinuum = true)) in the scene's world and its
/// simulation settings (only the integrator and step change), through the same SceneSimulation a bake uses.
StudyResult runStudy(const Scene& scene, const StudyOptions& options, std::ostream& log);

/// Flags the Pareto front (no other finite row both cheaper and more accurate) in the study's error kind:
/// run again after changing `result.error`.
void markPareto(StudyResult& result);

/// The cheapest finite row whose error (the study's kind) is at most `target`; nullptr if none.
const StudyRow* cheapestWithin(const StudyResult& result, double target);

/// `scene` with a study setting applied: the world's integrator and step, and the first object moved to
/// the setting's lattice over the same box with its material carried over. What `study --apply` writes.
Result<Scene> applySetting(const Scene& scene, const StudySetting& setting);

/// The three errors of a scene as it stands (e.g. a project written by --apply and read back), against
/// the study's reference: runs the scene as a bake does, and its own lattice converged in time.
struct Remeasured {
    double total = 0.0, integration = 0.0, model = 0.0;
    double error(StudyError kind) const;
};
Result<Remeasured> remeasure(const Scene& scene, const StudyResult& study);

/// The largest |error| of a lattice's modes against the solid (StudyRow::solidModeError): the CSV's column.
double worstModeError(const std::vector<double>& errors);

/// CSV, one row per cell.
std::string studyCsv(const StudyResult& result);
/// A markdown page: method, reference, baselines, the Pareto front, and every row sorted by cost.
std::string studyMarkdown(const StudyResult& result, const std::string& command);

}  // namespace softtouch::analysis
