#pragma once
/// Meshes made in code: test shapes, benchmark meshes, placeholders.

#include "core/geometry/mesh.h"

namespace softtouch {

/// A closed UV ellipsoid around `centre` with the given radii: `rings` latitude bands (>= 2) and
/// `segments` longitude steps (>= 3), single pole vertices, outward counter-clockwise triangles,
/// 2·segments·(rings−1) triangles, and the analytic unit normals.
Mesh makeUvEllipsoid(int rings, int segments, const Vec3& radii, const Vec3& centre = Vec3::Zero());

}  // namespace softtouch
