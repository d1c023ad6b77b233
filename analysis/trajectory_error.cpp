#include "analysis/trajectory_error.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace softtouch::analysis {

TrajectoryDistance trajectoryDistance(std::span<const Vec3f> run, std::span<const Vec3f> reference, double diagonal) {
    assert(run.size() == reference.size() && diagonal > 0.0);
    if (run.empty())
        return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    double sum = 0.0, worst = 0.0;
    for (std::size_t i = 0; i < run.size(); ++i) {
        const double squared = (run[i] - reference[i]).cast<double>().squaredNorm();
        sum += squared;
        worst = std::max(worst, squared);
    }
    return {std::sqrt(sum / double(run.size())) / diagonal, std::sqrt(worst) / diagonal};
}

}  // namespace softtouch::analysis
