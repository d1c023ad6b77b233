#pragma once
/// The interaction every contender of the paper's Table 1 is timed on: the same mesh, the same second
/// of a user pulling the object by a hand's width of its tip while a few vertices are held, the same
/// spring constants. Each contender (our lattice, a global mass-spring on every vertex, a local
/// mass-spring around the drag, Bullet's btSoftBody) simulates it and hands out the mesh positions at
/// the frame rate.

#include "core/geometry/lattice.h"
#include "core/geometry/mesh.h"

#include <algorithm>
#include <cmath>
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
    std::uint32_t dragVertex = 0;       ///< The vertex at the centre of what the user holds.
    double gripRadius = 0.0;            ///< The drag pulls the mean of what lies within this distance of the
                                        ///< dragged vertex (m; makeScenario(): 10% of the diagonal): the ball of
                                        ///< material on the lattice and the solid, the surface on a mesh body
                                        ///< (surfaceGrip()). A single point's pull has no converged solid.
    Vec3 dragOffset = Vec3::Zero();     ///< Where it is pulled, relative to its rest position (m); the
                                        ///< target moves there linearly over the first half second, then holds.
    double dragStiffness = 50.0;        ///< Ks of the drag spring, N/m.
    double dragDamping = 0.5;           ///< Kd of the drag spring, N·s/m.
    std::vector<std::uint32_t> anchors; ///< Vertices held fixed (the paper's anchors).
    double localRadius = 0.0;           ///< The local mass-spring simulates the vertices within this distance
                                        ///< of the dragged one, m (makeScenario(): 25% of the diagonal).

    /// Drag target offset at time t (seconds).
    Vec3 dragOffsetAt(double t) const { return dragOffset * std::min(1.0, t / (0.5 * seconds)); }
    /// Steps of a run at dt / `stepDivision` (the converged runs take finer steps).
    int steps(int stepDivision = 1) const { return int(std::lround(seconds / dt)) * stepDivision; }
    /// Steps between two frames at dt / `stepDivision`.
    int stepsPerFrame(int stepDivision = 1) const {
        return std::max(1, int(std::lround(1.0 / (frameRate * dt)))) * stepDivision;
    }
    /// Frames a run hands out (60 for one second at 60 Hz).
    int frames() const { return steps() / stepsPerFrame(); }
};

/// A scenario on `mesh`: drag what lies within 10% of the diagonal of the vertex of largest x outward by 20% of
/// the diagonal, hold the 5% of vertices of smallest x; the local mass-spring's region reaches 25% of the
/// diagonal from the drag.
InteractionScenario makeScenario(Mesh mesh);

/// What a mesh body's drag holds: the surface within scenario.gripRadius of the dragged vertex, as vertex
/// weights summing to 1, each vertex weighted by its share of the surface (a third of its triangles' area), so
/// that the pull is the mean of the surface under the hand on a coarse mesh as on a fine one. Never empty: the
/// dragged vertex alone when nothing else is near.
std::vector<NodeWeight> surfaceGrip(const InteractionScenario& scenario);

/// A closed ellipsoid with exactly `triangles` triangles (a UV sphere; `triangles` must be
/// 2·segments·(rings−1) for some segments >= 3, rings >= 3 — every size of the paper's Table 1 is).
Mesh makeEllipsoid(int triangles, const Vec3& radii = Vec3(0.5, 0.35, 0.25));

}  // namespace softtouch::bench
