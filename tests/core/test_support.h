#pragma once
// Shared helpers of the core tests: small meshes made in code.

#include "core/mesh.h"
#include "core/primitives.h"

#include <cmath>
#include <numbers>

namespace softtouch::test {

/// UV sphere of radius r around c, with analytic unit normals.
inline Mesh makeSphere(double r, const Vec3& c, int rings = 24, int segments = 48) {
    return makeUvEllipsoid(rings, segments, Vec3::Constant(r), c);
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
