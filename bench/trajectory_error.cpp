#include "bench/trajectory_error.h"

#include <cassert>
#include <cmath>
#include <limits>

namespace softtouch::bench {

double trajectoryError(std::span<const Vec3f> run, std::span<const Vec3f> reference, double diagonal) {
    assert(run.size() == reference.size() && diagonal > 0.0);
    if (run.empty())
        return std::numeric_limits<double>::quiet_NaN();
    double sum = 0.0;
    for (std::size_t i = 0; i < run.size(); ++i)
        sum += (run[i] - reference[i]).cast<double>().squaredNorm();
    return std::sqrt(sum / double(run.size())) / diagonal;
}

}  // namespace softtouch::bench
