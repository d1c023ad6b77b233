#pragma once
/// The paper's Table 1 redone at equal response and graded at equal accuracy against one reference.
///
/// For one mesh size (measureTable1Size()):
///  1. Equal response. Every contender's stiffness is scaled (equal_response.h) until what its
///     drag holds reaches the same static displacement under the same pull: a stated fraction of the
///     mesh's bounding-box diagonal (Table1Options::targetFraction; why that and not the lattice's own
///     displacement: docs/measurements/performance.md).
///  2. Each peer at its best. The mass-springs run implicit Euler (at the scenario's step) and XPBD
///     with 1, 2, 4, … substeps up to the first as accurate as implicit Euler (within 25%, or within
///     0.2% of the diagonal); the cheaper of the two at that accuracy is the peer's time (where no count
///     tried gets there, the cheaper of implicit Euler and the most accurate XPBD: never overstated). Bullet runs as many position iterations as its static
///     displacement needs to converge (within 1% of every larger count tried), and its default of one.
///     The lattice runs implicit Euler (the paper's row), XPBD and Verlet.
///  3. Every run reports its time, the static displacement of its body, its calibration scale and its
///     error against its own converged run (trajectory_error.h): the same body and stiffness run much
///     finer (Verlet at dt/4, substepped below its stability bound, for the lattice and the local
///     mass-spring; XPBD at 128 substeps for the global one; 8x the iterations for Bullet).
///  4. Equal accuracy. One reference for all (solid_reference.h): the converged solid, calibrated to the same
///     static displacement. Every run, and every run of a mesh body on a smaller size carried onto this mesh
///     (surface_transfer.h, the carrying timed into its cost), gets its mesh-wide RMS distance from it. The
///     lattice's paper row sets the accuracy asked for; each contender's time at equal accuracy is its
///     cheapest run at least that close to the solid (any solver and count tried; for the mesh bodies, on
///     any mesh size up to this one), timed best of Table1Options::timings. Where no run of a contender gets that close, its most accurate
///     run stands in, marked: the contender never matches the lattice here, and no speed ratio is claimed.

#include "bench/contenders.h"
#include "bench/equal_response.h"
#include "bench/solid_reference.h"

#include <ostream>
#include <span>
#include <string>
#include <vector>

namespace softtouch::bench {

/// What to measure.
struct Table1Options {
    double targetFraction = 0.18;     ///< The common static displacement, as a fraction of the mesh's bounding-box
                                      ///< diagonal (the drag reaches 0.2). (0, 0.2).
    double implicitBudgetSeconds = 0; ///< The global mass-spring's implicit Euler stops after this much wall time
                                      ///< and its time is extrapolated (it takes minutes at 24,928 triangles);
                                      ///< 0: never stopped. Other runs are never stopped.
    bool bullet = true;               ///< Run Bullet where it is available.
    SolidReferenceOptions reference;  ///< The common reference's refinement.
    int timings = 3;                  ///< Each run the table shows is timed this often; the fastest counts.
};

/// One timed run of one contender.
struct Table1Run {
    Contender contender = Contender::Lattice;
    std::string solver;         ///< "implicit-euler", "xpbd", "verlet" or "bullet".
    int iterations = 1;         ///< XPBD substeps per step, Bullet iterations per step; 1 otherwise.
    double seconds = 0.0;       ///< Wall time for the one-second scenario (extrapolated when `stopped`); for the
                                ///< runs the table shows (`best`, Bullet's default), the fastest of
                                ///< Table1Options::timings.
    bool stopped = false;       ///< Stopped at Table1Options::implicitBudgetSeconds; `seconds` extrapolated and
                                ///< `error` over the frames it reached.
    double scale = 1.0;         ///< Stiffness scale of its body (the calibration's).
    double displacement = 0.0;  ///< Static displacement of its body at that scale (m; Bullet: at its iterations).
    double error = 0.0;         ///< RMS error against its own converged run, fraction of the diagonal.
    bool finite = true;         ///< Every position it produced was finite.
    std::string role;           ///< Why it ran: "paper" (the lattice's row), "other" (the lattice's other solvers),
                                ///< "implicit", "ladder" (an XPBD substep count tried), "matched" (the first XPBD
                                ///< as accurate as implicit Euler), "most accurate" (the last XPBD tried when none
                                ///< matched), "converged" / "default" (Bullet).
    bool best = false;          ///< The contender's time in the table (its cheapest at comparable accuracy).
    double solidError = 0.0;    ///< RMS distance from the common reference (the converged solid), fraction of
                                ///< the diagonal; NaN for a stopped run (it has no frames past its stop).
};

/// A run graded against this size's reference: one of this size's, or one of a smaller size's carried onto
/// this mesh.
struct Table1Graded {
    Contender contender = Contender::Lattice;
    int triangles = 0;          ///< The mesh it ran on.
    std::string solver;
    int iterations = 1;
    double scale = 1.0;         ///< Its calibration's stiffness scale (at its own size).
    double seconds = 0.0;       ///< Its time, plus carrying its frames onto this mesh when it ran on another.
    double carrying = 0.0;      ///< Of `seconds`, carrying its frames onto this mesh (0 on its own).
    double solidError = 0.0;    ///< RMS distance from this size's reference, fraction of the diagonal.
};

/// A contender at equal accuracy.
struct Table1Pick {
    Table1Graded run;           ///< Its cheapest run at least as close to the solid as the lattice's paper row;
                                ///< its most accurate when none is (`reached` false).
    bool reached = false;
    double fastest = 0.0;       ///< Best of Table1Options::timings runs of that setting, s.
    double slowest = 0.0;       ///< Slowest of them, s (the spread).
};

/// What was found for one contender at one size.
struct Table1Contender {
    Contender contender = Contender::Lattice;
    Calibration calibration;             ///< Scale, displacement and every evaluation.
    std::string reference;               ///< Its converged run, in words ("verlet", "xpbd x64", "bullet x64").
    double accuracyGoal = 0.0;           ///< Mass-springs: the error XPBD had to reach, within 25% (implicit Euler's,
                                         ///< on the frames implicit Euler reached, or 0.2% of the diagonal if larger).
    bool accuracyMatched = true;         ///< Mass-springs: an XPBD substep count tried reached it. When not, the
                                         ///< contender's time is the cheaper of implicit Euler and its most accurate
                                         ///< XPBD, and the lattice's ratio to it is a lower bound.
    int bulletIterations = 0;            ///< Bullet: the converged iteration count (calibrated at it).
    std::vector<CalibrationStep> iterationCheck; ///< Bullet: static displacement per iteration count tried
                                                 ///< (`scale` holds the count), at the first scale tried.
};

/// One size of the table.
struct Table1Size {
    int triangles = 0;
    std::size_t vertices = 0;
    double diagonal = 0.0;            ///< Bounding-box diagonal, m.
    double target = 0.0;              ///< Common static displacement, m.
    std::vector<Table1Contender> contenders;
    std::vector<Table1Run> runs;
    Mesh mesh;                                   ///< The ellipsoid (rest), for the larger sizes' carrying.
    std::vector<std::vector<Vec3f>> runFrames;   ///< Each run's mesh frames (runs[i]); empty for a stopped run.
    SolidReference reference;                    ///< The common reference, calibrated to the same target.
    double accuracyGoal = 0.0;                   ///< The lattice's paper row's distance from the solid.
    std::vector<Table1Graded> graded;            ///< Every run graded, this size's first.
    std::vector<Table1Pick> picks;               ///< One per contender, in kContenders' order.
    /// The pick of `contender` (nullptr when it did not run).
    const Table1Pick* pick(Contender contender) const;
    /// The run marked best for `contender` (nullptr when it did not run).
    const Table1Run* best(Contender contender) const;
    /// The first run of `contender` in `role` (nullptr when none).
    const Table1Run* find(Contender contender, const std::string& role) const;
    /// What was found for `contender` (nullptr when it did not run).
    const Table1Contender* about(Contender contender) const;
};

/// Calibrates, runs and measures every contender on a `triangles` ellipsoid. `smaller`: the sizes measured
/// before, smallest first (or none): their runs are graded here too, and the last gives the calibrations
/// their first guesses. Progress goes to `log`.
Table1Size measureTable1Size(int triangles, const Table1Options& options, std::span<const Table1Size> smaller,
                             std::ostream& log);

}  // namespace softtouch::bench
