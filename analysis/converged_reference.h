#pragma once
/// The truth a speed/accuracy study grades against: the scene's clip run by the solid element (the
/// Galerkin solid on the lattice's own basis, core/body/element_body.h) refined in space and in time until
/// refining further barely moves the clip, with an estimate of how far it still is from the limit.
///
/// Space: Bezier nets of rising degree over each object's own box (4x4x4, 6x6x6, 8x8x8; 8 per axis is the
/// highest degree SoftTouch builds), the painted material carried as a continuum. Time: Verlet (second
/// order, no numerical damping, substepped below its stability bound) at a step far below the clip's motion,
/// checked at half that step on the coarsest net (a finer net substeps at least as finely). Each level's
/// change from the one before is measured on the exported mesh, RMS over every vertex of every frame,
/// relative to the mesh's bounding-box diagonal, the worst object deciding. The uncertainty of the finest
/// run is the estimate of its remaining distance to the limit:
///
///   space: with changes d₁ (4→6) and d₂ (6→8) and r = d₂/d₁ < 1, the rest of a geometric series,
///          d₂ r / (1 − r); d₂ itself when the changes do not shrink (no estimate is then claimed below it);
///   time:  Verlet's error falls fourfold when the step halves, so the run at the full step is 4/3 of the
///          change off (Richardson).
///
/// A target below ten times the uncertainty cannot be certified against it (a tenth of the target is
/// what the reference may be off by).

#include "analysis/clip_frames.h"

#include <functional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

namespace softtouch::analysis {

/// One rung of the refinement.
struct ReferenceLevel {
    std::string what;         ///< "solid 6x6x6 bezier, verlet, dt 1/4000 s".
    double change = 0.0;      ///< Worst object's RMS distance to the rung before / diagonal; NaN for the first.
    double seconds = 0.0;     ///< Wall time the rung took.
};

/// One line for `level` in a refinement's log: what it ran, its time and, after the first, how far it moved
/// the mesh from the rung before.
void logReferenceLevel(const ReferenceLevel& level, std::ostream& log);

/// The converged solid's clip.
struct ConvergedReference {
    ClipMeshFrames frames;              ///< The finest rung's mesh frames: the reference.
    double uncertainty = 0.0;           ///< Estimated RMS distance of `frames` from the limit / diagonal (worst object).
    double spaceUncertainty = 0.0;      ///< Its part from the lattice.
    double timeUncertainty = 0.0;       ///< Its part from the step.
    bool spaceConverging = true;        ///< The changes shrank as the net was refined (else no estimate below the last change).
    std::vector<ReferenceLevel> levels; ///< Every rung, coarsest first.
    std::string description;            ///< One line: what the reference is.
    double dt = 0.0;                    ///< Step of the reference run, s.
    bool cancelled = false;             ///< The progress callback stopped it.
};

/// How to make it.
struct ReferenceOptions {
    std::vector<int> nodes = {4, 6, 8};  ///< Bezier nodes per axis, coarsest first; the last is the reference.
    double dt = 1.0 / 4000;              ///< Step of the reference; the coarsest net also runs at half of it.
    /// Called before each frame of each rung with the fraction done; returning false cancels at that frame.
    std::function<bool(double)> progress;
};

/// The ladder of a quick study (the editor's dock, `study --quick`): 3x3x3, 4x4x4, 6x6x6. A minute's less
/// work, a larger uncertainty, which is printed and enforced like any other.
ReferenceOptions quickReference();

/// `scene`, every object on an n x n x n Bezier net over its own box, run by the solid element.
Result<Scene> solidOnBezier(const Scene& scene, int nodes);

/// Runs the refinement for `clip` of `scene` (and its `library`, for the clip's source), logging each rung.
/// Fails, saying why, when the scene cannot run the solid element (a spring-model material, voids, strain
/// limits, volume preservation) or the clip cannot be played on other lattices (a take or keys on the nodes).
Result<ConvergedReference> convergedReference(const Scene& scene, const ClipLibrary& library, const Clip& clip,
                                              const ReferenceOptions& options, std::ostream& log);

/// How far the finest run of a refinement still is from the limit (the estimates above), relative to the
/// diagonal. `spaceChanges`: each net's change from the one before, coarsest first (none: infinite, nothing
/// says how far). `timeChange`: Verlet at half the step against the full step on one net.
struct RefinementUncertainty {
    double space = 0.0;
    double time = 0.0;
    double total = 0.0;
    bool spaceConverging = true;  ///< The changes shrank (else `space` is the last change, no estimate below it).
};
RefinementUncertainty refinementUncertainty(std::span<const double> spaceChanges, double timeChange);

/// The smallest target `reference` certifies: ten times its uncertainty (a tenth of the target is what the
/// reference may be off by); infinite when it has no finite uncertainty.
double certifiedFrom(const ConvergedReference& reference);
/// Whether `target` can be certified against `reference`: at least certifiedFrom(reference).
bool certifiable(const ConvergedReference& reference, double target);

}  // namespace softtouch::analysis
