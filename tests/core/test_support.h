#pragma once
// Shared helpers of the core tests: small meshes made in code.

#include "core/mesh.h"

#include <cmath>
#include <numbers>

namespace softtouch::test {

/// UV sphere of radius r around c, with analytic unit normals.
inline Mesh makeSphere(double r, const Vec3& c, int rings = 24, int segments = 48) {
    Mesh m;
    for (int i = 0; i <= rings; ++i) {
        const double theta = std::numbers::pi * i / rings;
        for (int j = 0; j < segments; ++j) {
            if ((i == 0 || i == rings) && j > 0)
                break;  // single pole vertex
            const double phi = 2.0 * std::numbers::pi * j / segments;
            const Vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            m.positions.push_back((c + r * n).cast<float>());
            m.normals.push_back(n.cast<float>());
        }
    }
    auto idx = [&](int i, int j) -> std::uint32_t {
        if (i == 0) return 0;
        if (i == rings) return std::uint32_t(1 + (rings - 1) * segments);
        return std::uint32_t(1 + (i - 1) * segments + (j % segments));
    };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            if (i > 0) m.triangles.push_back({idx(i, j), idx(i, j + 1), idx(i + 1, j)});
            if (i < rings - 1) m.triangles.push_back({idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j)});
        }
    return m;
}

/// Deterministic pseudo-random points in a box (a "mesh" of scattered vertices for map tests).
inline std::vector<Vec3f> scatter(int count, const Vec3& lo, const Vec3& hi, unsigned seed = 1) {
    std::vector<Vec3f> out;
    unsigned s = seed;
    auto next = [&] { s = s * 1664525u + 1013904223u; return double(s >> 8) / double(1u << 24); };
    for (int i = 0; i < count; ++i) {
        const Vec3 t(next(), next(), next());
        out.push_back((lo + t.cwiseProduct(hi - lo)).cast<float>());
    }
    return out;
}

}  // namespace softtouch::test
