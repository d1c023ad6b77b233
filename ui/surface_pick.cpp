#include "ui/surface_pick.h"

namespace softtouch::ui {

std::optional<SurfaceHit> pickSurface(const Ray& ray, std::span<const Vec3f> positions,
                                      std::span<const std::array<std::uint32_t, 3>> triangles) {
    std::optional<SurfaceHit> best;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const Vec3 a = positions[triangles[t][0]].cast<double>();
        const Vec3 e1 = positions[triangles[t][1]].cast<double>() - a;
        const Vec3 e2 = positions[triangles[t][2]].cast<double>() - a;
        const Vec3 p = ray.direction.cross(e2);
        const double det = e1.dot(p);
        if (std::abs(det) < 1e-18)
            continue;
        const double inv = 1.0 / det;
        const Vec3 s = ray.origin - a;
        const double u = s.dot(p) * inv;
        if (u < 0.0 || u > 1.0)
            continue;
        const Vec3 q = s.cross(e1);
        const double v = ray.direction.dot(q) * inv;
        if (v < 0.0 || u + v > 1.0)
            continue;
        const double d = e2.dot(q) * inv;
        if (d <= 0.0 || (best && d >= best->distance))
            continue;
        best = SurfaceHit{std::uint32_t(t), Vec3(1.0 - u - v, u, v), d, ray.origin + d * ray.direction};
    }
    return best;
}

}  // namespace softtouch::ui
