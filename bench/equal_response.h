#pragma once
/// Equal response: the contenders of Table 1 are only comparable when they are the same object. Each
/// contender's stiffness is scaled until what its drag holds reaches a common static displacement
/// under the same pull (the drag held at its final offset until the body settles).

#include <functional>
#include <vector>

namespace softtouch::bench {

/// How closely, and in how many settles at most, Table 1 brings every body to the common displacement
/// (relative; equal response is asked for within 5%).
inline constexpr double kEqualResponseTolerance = 0.01;
inline constexpr int kEqualResponseEvaluations = 8;

/// One evaluation of the calibration.
struct CalibrationStep {
    double scale = 0.0;        ///< Stiffness scale tried.
    double displacement = 0.0; ///< Static displacement it gave, m.
    int settleSteps = 0;       ///< Steps its settle took.
};

/// Where the calibration ended.
struct Calibration {
    double scale = 1.0;          ///< The stiffness scale found (multiplies scenario.stiffness).
    double displacement = 0.0;   ///< The static displacement at that scale, m.
    bool converged = false;      ///< Within the tolerance of the target.
    bool saturated = false;      ///< Stopped because stiffening (or softening) no longer moved the displacement:
                                 ///< the target is out of this contender's reach (`displacement` is its closest).
    std::vector<CalibrationStep> steps; ///< Every evaluation, in order.
};

/// A contender's static displacement (m) at a stiffness scale; with the number of settle steps it took.
using StaticDisplacement = std::function<CalibrationStep(double scale)>;

/// Finds the stiffness scale whose static displacement is `target` (m) within `tolerance` (relative),
/// starting from `firstScale`, in at most `maxEvaluations` settles. `reach` is where what the drag
/// holds would go with no body at all (the drag's offset, m; > target).
///
/// The body under the drag is a spring k_b·scale in series with the drag spring Ks, so a linear
/// body would move d = reach·Ks / (Ks + k_b·scale). The first step solves that model for the scale
/// (one settle tells k_b); after it the search is a secant on log(displacement) against log(scale)
/// (the body is not linear), kept inside the bracket once the target is bracketed (bisection in
/// log(scale) when the secant leaves it). It gives up, saturated, when a tenfold change of scale moved
/// the displacement by less than 0.2% of itself and the target was not bracketed (a position solver's
/// links stop stiffening once they are fully projected every iteration). The result is the evaluation
/// closest to the target.
Calibration calibrate(const StaticDisplacement& displacement, double target, double reach, double firstScale,
                      double tolerance = 0.01, int maxEvaluations = 10);

}  // namespace softtouch::bench
