#pragma once
/// A per-node field from values given at points: a weight map painted on a mesh's vertices in another tool (a
/// Blender vertex group) carried onto the lattice's nodes, the way the editor's brush leaves it there.

#include "core/base/result.h"
#include "core/base/types.h"
#include "core/geometry/lattice.h"

#include <span>
#include <vector>

namespace softtouch {

/// One value at one place, in the scene's coordinates (metres).
struct PointValue {
    Vec3 point = Vec3::Zero(); ///< Where, in the frame the lattice's box is in.
    double value = 0.0;        ///< What the field is there.
};

/// Each node's value is the average of the points' values weighted by the node's basis function at each point,
/// Σ_p N_i(p) v_p / Σ_p N_i(p): a convex mix, so the field stays within the points' range (weights in [0, 1]
/// stay there), 1 at every point gives exactly 1 on every node (the two sums are the same numbers), and a node
/// takes the values of the points it moves most. A node whose basis weighs no point (a B-spline node far from the mesh) takes the
/// value of the point nearest its rest place. Points outside the box count at their nearest place on it.
/// Errors on no points or a value that is not finite.
Result<std::vector<double>> fitNodeField(const Lattice& lattice, std::span<const PointValue> points);

}  // namespace softtouch
