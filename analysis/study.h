#pragma once
/// `softtouch-cli study`: the speed/accuracy trade measured on a scene's clip, as it is exported. For every
/// integrator × time step × lattice resolution, applied to every object: the wall time the clip costs
/// (physics and mesh deformation, best of repeats, with their spread), and the errors of the exported mesh
/// against the converged solid (analysis/converged_reference.h), every object measured and the worst one
/// deciding: integration error (this lattice against itself converged in time) and model error (this
/// lattice converged in time against the converged solid) kept apart, beside the clip's own motion and the
/// do-nothing baseline. Also the integrator's character in free vibration (energy drift, amplitude lost
/// per period, frequency error). Reported as CSV, a markdown table with the Pareto front, and data for a
/// plot; a pick can be written into a project and re-measured as written.

#include "analysis/converged_reference.h"
#include "core/scene/scene.h"

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
    Total,        ///< Against the converged solid: integration and model error together.
    Integration,  ///< Against this same lattice converged in time: what the integrator and step cost.
    Model,        ///< This lattice converged in time against the converged solid: what the resolution costs.
};
std::string_view studyErrorName(StudyError kind);              ///< "total", "integration", "model".
std::optional<StudyError> parseStudyError(std::string_view name);

/// The settings a study row measures.
struct StudySetting {
    IntegratorKind integrator = IntegratorKind::Verlet;
    double dt = 1.0 / 240;     ///< Step, s.
    LatticeShape lattice;      ///< Kind and nodes per axis, over each object's box.
    BodyElement element = BodyElement::Springs;  ///< What every object's material runs on.
};

/// The largest lattice (nodes) the default grid runs the solid element on, and the quick grid's: its runs converged
/// in time (Verlet at the study's fine step, substepping the consistent mass) take minutes on 8^3 nets, and tens of
/// seconds on a 6^3 B-spline, more than the editor's quick study may take.
inline constexpr int kStudyElementNodes = 216;
inline constexpr int kQuickStudyElementNodes = 64;

/// The scene's own setting: the world's integrator and step, the first object's lattice and element.
StudySetting sceneSetting(const Scene& scene);
/// Whether two settings are the same (the steps equal within rounding): how a row is found to be the scene's own.
bool sameSetting(const StudySetting& a, const StudySetting& b);

/// What to run.
struct StudyOptions {
    bool quick = false;        ///< Fewer steps and resolutions (for tests and the editor); the same clip.
    /// The clip measured, by name; empty: what `bake` plays without --clip (the default clip or the drivers).
    std::string clip;
    StudyError error = StudyError::Total;
    int repeats = 5;           ///< Timed runs per setting; the cost is the fastest. [1, 100].
    /// What a bake does with the frames it played, timed with every run so that a row's cost is what its bake pays:
    /// physics, mesh deformation and writing (the CLI writes a PC2 cache and its rest mesh, as `bake` does by
    /// default, to a scratch folder). Empty: nothing written, the cost is the frames alone (the editor's dock,
    /// whose cost is the viewport's frame time).
    std::function<Status(const ClipMeshFrames&)> write;
    /// What `write` writes, for the report ("a PC2 cache and its rest mesh"); empty when nothing is.
    std::string written;
    /// The grid; empty: the default (quick) grid. Lattices are carried over each object's box.
    std::vector<LatticeShape> lattices;
    std::vector<IntegratorKind> integrators;
    std::vector<double> steps;
    /// The elements; empty: springs and the solid element. The solid element's rows run on the grid's lattices of
    /// at most kStudyElementNodes nodes (kQuickStudyElementNodes when quick; every given lattice when `lattices`
    /// is set) with implicit Euler (the given integrators but XPBD, which it cannot run, when `integrators` is
    /// set): explicit schemes substep it far harder than springs, so their element rows cost more for the same
    /// error.
    std::vector<BodyElement> elements;
    /// Also measure the scene's own setting (integrator, step and lattice of its first object).
    bool includeCurrent = true;
    /// How the converged solid is made (its ladder of nets and its step).
    ReferenceOptions reference;
    /// A reference made before for this very scene and clip (a second study of it): used instead of making one.
    std::shared_ptr<const ConvergedReference> given;
    /// The error target the study is run for, if any: when the reference cannot certify it (refusalOfTarget),
    /// the study stops before the grid and says why in `failure`.
    std::optional<double> target;
    /// Called between runs with the fraction done; returning false cancels (the result then says so). While the
    /// study makes its reference, that runs on a second thread and calls this too: never two calls at once, but
    /// not always from the caller's thread.
    std::function<bool(double)> progress;
};

/// One cell of the study.
struct StudyRow {
    IntegratorKind integrator = IntegratorKind::ImplicitEuler;
    double dt = 0.0;                   ///< Step, s.
    LatticeShape lattice;              ///< Kind and nodes per axis.
    BodyElement element = BodyElement::Springs;
    std::string resolution;            ///< studyModelName(lattice, element), e.g. "4x4x4 bezier", "4x4x4 bezier solid".
    int nodes = 0;                     ///< Lattice nodes.
    /// Wall seconds per second of clip: the clip's physics, mesh deformation and writing (StudyOptions::write), the
    /// fastest of the repeats.
    double costPerSecond = 0.0;
    double costSpread = 0.0;           ///< (slowest − fastest) / fastest of the repeats.
    /// Total: RMS vertex error over all frames against the reference / mesh diagonal, the worst object's.
    double rmsError = 0.0;
    double maxError = 0.0;             ///< Largest vertex error over all frames and objects, same reference / diagonal.
    double timeError = 0.0;            ///< Integration: RMS error against this same lattice converged in time (worst object).
    double modelError = 0.0;           ///< Model: this lattice converged in time against the reference (worst object).
    std::vector<double> objectErrors;  ///< Total error of each object, in scene order.
    double energyDrift = 0.0;          ///< Free vibration, no damping: (E_end − E_0) / E_0.
    double amplitudeLoss = 0.0;        ///< Free vibration: fraction of amplitude lost per period.
    double frequencyError = 0.0;       ///< Free vibration: (f − f_ref) / f_ref, f_ref the same lattice converged.
    /// The lattice's three lowest modes against the converged solid of its material (core/modes/solid_modes.h):
    /// f_lattice / f_solid − 1 each. Empty when that solid does not converge (point anchors) or cannot be
    /// analysed. Like the model error it belongs to the lattice, but it needs no finest lattice.
    std::vector<double> solidModeError;
    bool finite = true;                ///< No non-finite frame.
    bool pareto = false;               ///< No other row is both cheaper and more accurate (in the study's error).
    bool current = false;              ///< The scene's own setting.

    double error(StudyError kind) const;
    StudySetting setting() const { return {integrator, dt, lattice, element}; }
};

/// The whole study.
struct StudyResult {
    std::vector<StudyRow> rows;
    StudyError error = StudyError::Total;  ///< The error the front and picks use.
    Clip clip;                         ///< The clip measured (named "drivers": the scene's drivers from rest).
    std::vector<std::string> objects;  ///< Names of the objects measured, in scene order.
    /// The converged solid every row is graded against (its frames, ladder and uncertainty).
    std::shared_ptr<const ConvergedReference> reference;
    double convergedDt = 1.0 / 4000;   ///< Step of each lattice's run converged in time (Verlet), s.
    double restError = 0.0;            ///< The do-nothing baseline: the bodies at rest against the reference (worst object).
    double motionAmplitude = 0.0;      ///< Largest vertex displacement of the reference from rest / diagonal.
    std::string failure;               ///< Why there are no rows (the reference could not be made); empty otherwise.
    std::string written;               ///< What each timed run also wrote (StudyOptions::written); empty: nothing.
    bool cancelled = false;            ///< The progress callback stopped it; rows are those measured so far.
    /// The reference's uncertainty (ConvergedReference::uncertainty); infinite without one.
    double referenceUncertainty() const;
    /// The smallest target the reference certifies (certifiedFrom()); infinite without one.
    double certifiedFrom() const;
};

/// "4x4x4 bezier": how the study names a lattice shape.
std::string latticeShapeName(const LatticeShape& shape);
/// "4x4x4 bezier" for springs, "4x4x4 bezier solid" for the solid element: how the study names a body model.
std::string studyModelName(const LatticeShape& shape, BodyElement element);

/// Runs the study on every object of `scene` (their drivers, anchors and painted material, carried to every
/// resolution with resampleMaterial(..., keepContinuum = true)) in the scene's world and its simulation
/// settings (only the integrator and step change), playing the clip of `library` as a bake does.
StudyResult runStudy(const Scene& scene, const ClipLibrary& library, const StudyOptions& options, std::ostream& log);

/// Flags the Pareto front (no other finite row both cheaper and more accurate) in the study's error kind:
/// run again after changing `result.error`.
void markPareto(StudyResult& result);

/// The cheapest finite row whose error (the study's kind) is at most `target`; nullptr if none. Rows whose
/// costs lie within the cheapest one's spread are a tie, which the smaller error wins.
const StudyRow* cheapestWithin(const StudyResult& result, double target);

/// Why `target` cannot be certified by this study (empty when it can): doing nothing meets it, or it lies
/// below ten times the reference's uncertainty.
std::string refusalOfTarget(const StudyResult& result, double target);

/// `scene` with a study setting applied: the world's integrator and step, and every object moved to the
/// setting's lattice over its own box with its material carried over. What `study --apply` writes.
Result<Scene> applySetting(const Scene& scene, const StudySetting& setting);

/// The three errors of a scene as it stands (e.g. a project written by --apply and read back), against
/// the study's reference, on the study's clip: runs the clip as a bake does, and its own lattice converged in time.
struct Remeasured {
    double total = 0.0, integration = 0.0, model = 0.0;
    double error(StudyError kind) const;
};
Result<Remeasured> remeasure(const Scene& scene, const ClipLibrary& library, const StudyResult& study);

/// The largest |error| of a lattice's modes against the solid (StudyRow::solidModeError): the CSV's column.
double worstModeError(const std::vector<double>& errors);

/// CSV, one row per cell.
std::string studyCsv(const StudyResult& result);
/// A markdown page: method, reference, baselines, the Pareto front, and every row sorted by cost.
std::string studyMarkdown(const StudyResult& result, const std::string& command);

}  // namespace softtouch::analysis
