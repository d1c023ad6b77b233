#include "bench/equal_response.h"

#include <algorithm>
#include <cmath>

namespace softtouch::bench {

Calibration calibrate(const StaticDisplacement& displacement, double target, double reach, double firstScale,
                      double tolerance, int maxEvaluations) {
    Calibration result;
    // Points as (log scale, log displacement − log target): the root is the scale wanted.
    double lowX = 0.0, highX = 0.0;  // bracket: residual > 0 at lowX (too soft), < 0 at highX
    bool haveLow = false, haveHigh = false;
    double lastX = 0.0, lastY = 0.0;
    double x = std::log(firstScale);
    for (int i = 0; i < maxEvaluations; ++i) {
        const CalibrationStep step = displacement(std::exp(x));
        result.steps.push_back(step);
        if (!(step.displacement > 0.0) || !std::isfinite(step.displacement))
            break;  // a body that did not settle or did not move cannot be calibrated
        const double y = std::log(step.displacement / target);
        if (result.steps.size() == 1 || std::abs(y) < std::abs(std::log(result.displacement / target))) {
            result.scale = step.scale;
            result.displacement = step.displacement;
        }
        if (std::abs(step.displacement / target - 1.0) <= tolerance) {
            result.converged = true;
            break;
        }
        if (i > 0 && !(haveLow && haveHigh) && std::abs(x - lastX) >= std::log(10.0) &&
            std::abs(y - lastY) < 0.002 && (y > 0.0) == (lastY > 0.0)) {
            result.saturated = true;
            break;
        }
        if (y > 0.0) {
            lowX = haveLow ? std::max(lowX, x) : x;
            haveLow = true;
        } else {
            highX = haveHigh ? std::min(highX, x) : x;
            haveHigh = true;
        }
        double next;
        if (i == 0) {
            // Series springs: reach/d − 1 = k_b·scale/Ks, so the scale goes with reach/d − 1.
            const double now = reach / step.displacement - 1.0, wanted = reach / target - 1.0;
            next = x + (now > 0.0 ? std::log(wanted / now) : 1.0);
        } else {
            const double slope = (y - lastY) / (x - lastX);
            next = slope < 0.0 ? x - y / slope : x + (y > 0.0 ? 1.0 : -1.0);  // a rising curve: step out
        }
        next = std::clamp(next, x - 3.0, x + 3.0);  // at most 20x per evaluation
        if (haveLow && haveHigh && !(next > lowX && next < highX))
            next = 0.5 * (lowX + highX);
        lastX = x;
        lastY = y;
        x = next;
    }
    return result;
}

}  // namespace softtouch::bench
