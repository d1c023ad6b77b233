#pragma once
// Shared helpers of the core tests: small meshes made in code.

#include "core/geometry/mesh.h"
#include "core/geometry/primitives.h"
#include "core/scene/scene.h"

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

/// One object: a ball of radius 0.5 in a 4x4x4 Bezier lattice (0.01 kg, 80 N/m, 0.5 N·s/m per node)
/// whose bottom layer of nodes is pinned, so a pulled ball stretches and swings back instead of flying off.
inline Scene anchoredBallScene() {
    Scene scene;
    SceneObject object;
    object.name = "ball";
    object.mesh = makeSphere(0.5, Vec3::Zero(), 12, 24);
    object.lattice = Lattice::create(LatticeShape{}, fitBox(object.mesh->positions).value()).value();
    object.material = uniformMaterial(object.lattice, 0.01, 80.0, 0.5);
    for (int k = 0; k < object.lattice.count(2); ++k)
        for (int i = 0; i < object.lattice.count(0); ++i)
            object.material.anchor[std::size_t(object.lattice.index(i, 0, k))] = AnchorMode::Pinned;
    scene.objects.push_back(std::move(object));
    return scene;
}

}  // namespace softtouch::test
