#pragma once
/// Picking a point on a (deformed) triangle mesh under the cursor, so a drag grabs the surface the
/// user clicked and not only the nearest lattice node.

#include "core/geometry/mesh.h"
#include "ui/orbit_camera.h"

#include <optional>
#include <span>

namespace softtouch::ui {

/// Where a ray first meets a mesh.
struct SurfaceHit {
    std::uint32_t triangle = 0;     ///< Triangle index.
    Vec3 barycentric = Vec3::Zero();///< Weights of the triangle's three vertices; sum 1.
    double distance = 0.0;          ///< Along the ray, metres.
    Vec3 point = Vec3::Zero();      ///< World point hit.
};

/// First hit of `ray` on the triangles (both faces count), or nothing (Möller–Trumbore, 1997).
std::optional<SurfaceHit> pickSurface(const Ray& ray, std::span<const Vec3f> positions,
                                      std::span<const std::array<std::uint32_t, 3>> triangles);

}  // namespace softtouch::ui
