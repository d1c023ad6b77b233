#pragma once
/// The interaction every contender of the paper's Table 1 is timed on: the same mesh, the same second
/// of a user pulling one vertex while a few vertices are held, the same spring constants. Each
/// contender (our lattice, a global mass-spring on every vertex, a local mass-spring around the
/// drag, Bullet's btSoftBody) simulates it and hands out the mesh positions at the frame rate.

#include "core/mesh.h"

#include <cstdint>
#include <vector>

namespace softtouch::bench {

/// One second of dragging, identical for every contender.
struct InteractionScenario {
    Mesh mesh;                          ///< The object (positions, triangles).
    double seconds = 1.0;               ///< Simulated time, s.
    double dt = 1.0 / 240.0;            ///< Physics step, s.
    double frameRate = 60.0;            ///< Mesh positions are needed this often (the screen), Hz.
    double stiffness = 80.0;            ///< Per spring, N/m (the paper's 80.0).
    double damping = 0.9;               ///< Per spring, N·s/m (the paper's 0.9).
    double totalMass = 1.0;             ///< Of the whole object, kg.
    std::uint32_t dragVertex = 0;       ///< The vertex the user pulls.
    Vec3 dragOffset = Vec3::Zero();     ///< Where it is pulled, relative to its rest position (m); the
                                        ///< target moves there linearly over the first half second, then holds.
    double dragStiffness = 50.0;        ///< Ks of the drag spring, N/m.
    double dragDamping = 0.5;           ///< Kd of the drag spring, N·s/m.
    std::vector<std::uint32_t> anchors; ///< Vertices held fixed (the paper's anchors).

    /// Drag target offset at time t (seconds).
    Vec3 dragOffsetAt(double t) const { return dragOffset * std::min(1.0, t / (0.5 * seconds)); }
};

/// A scenario on `mesh`: drag the vertex of largest x outward by 20% of the diagonal, hold the 5% of
/// vertices of smallest x.
InteractionScenario makeScenario(Mesh mesh);

/// A closed ellipsoid with exactly `triangles` triangles (a UV sphere; `triangles` must be
/// 2·segments·(rings−1) for some segments >= 3, rings >= 3 — every size of the paper's Table 1 is).
Mesh makeEllipsoid(int triangles, const Vec3& radii = Vec3(0.5, 0.35, 0.25));

/// What a contender reports.
struct TimingResult {
    double seconds = 0.0;   ///< Wall-clock time for the whole scenario.
    bool finite = true;     ///< Every position it produced was finite.
    Vec3 dragVertexEnd = Vec3::Zero(); ///< Final position of the dragged vertex (a sanity check that it moved).
};

}  // namespace softtouch::bench
