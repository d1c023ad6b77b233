#include "core/geometry/primitives.h"

#include <cassert>
#include <cmath>
#include <numbers>

namespace softtouch {

Mesh makeUvEllipsoid(int rings, int segments, const Vec3& radii, const Vec3& centre) {
    assert(rings >= 2 && segments >= 3);
    Mesh m;
    for (int i = 0; i <= rings; ++i) {
        const double theta = std::numbers::pi * i / rings;
        for (int j = 0; j < segments; ++j) {
            if ((i == 0 || i == rings) && j > 0)
                break;  // single pole vertex
            const double phi = 2.0 * std::numbers::pi * j / segments;
            const Vec3 unit(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            m.positions.push_back((centre + unit.cwiseProduct(radii)).cast<float>());
            // The normal of an ellipsoid at a point is the gradient of (x/a)² + (y/b)² + (z/c)².
            m.normals.push_back(unit.cwiseQuotient(radii).normalized().cast<float>());
        }
    }
    auto index = [&](int i, int j) -> std::uint32_t {
        if (i == 0)
            return 0;
        if (i == rings)
            return std::uint32_t(1 + (rings - 1) * segments);
        return std::uint32_t(1 + (i - 1) * segments + (j % segments));
    };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            if (i > 0)
                m.triangles.push_back({index(i, j), index(i, j + 1), index(i + 1, j)});
            if (i < rings - 1)
                m.triangles.push_back({index(i, j + 1), index(i + 1, j + 1), index(i + 1, j)});
        }
    return m;
}

}  // namespace softtouch
