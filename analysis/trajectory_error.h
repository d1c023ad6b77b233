#pragma once
/// How far a run is from a converged run of the same body: the error every Table 1 row reports beside
/// its time, so that a contender cannot look fast by being inaccurate.

#include "core/base/types.h"

#include <span>

namespace softtouch::analysis {

/// How far one run of a mesh is from another, over every frame and every vertex, relative to `diagonal`
/// (the mesh's bounding-box diagonal, m): 0.01 means off by 1% of its size. Both runs hold the same
/// frames one after another (same count, same vertex order); NaN when they are empty.
struct TrajectoryDistance {
    double rms = 0.0;  ///< RMS of |run − reference|.
    double max = 0.0;  ///< Largest |run − reference|.
};
TrajectoryDistance trajectoryDistance(std::span<const Vec3f> run, std::span<const Vec3f> reference, double diagonal);

/// The RMS part: what a Table 1 row and the study report as error.
inline double trajectoryError(std::span<const Vec3f> run, std::span<const Vec3f> reference, double diagonal) {
    return trajectoryDistance(run, reference, diagonal).rms;
}

}  // namespace softtouch::analysis
