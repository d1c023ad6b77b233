#pragma once
/// How far a run is from a converged run of the same body: the error every Table 1 row reports beside
/// its time, so that a contender cannot look fast by being inaccurate.

#include "core/types.h"

#include <span>

namespace softtouch::bench {

/// RMS over every frame and every mesh vertex of |run − reference|, divided by `diagonal` (the mesh's
/// bounding-box diagonal, m): 0.01 means the mesh is off by 1% of its size on average. Both runs hand
/// out the same frames (same count, same vertex order).
double trajectoryError(std::span<const Vec3f> run, std::span<const Vec3f> reference, double diagonal);

}  // namespace softtouch::bench
