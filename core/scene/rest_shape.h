#pragma once
/// Editing an object's rest shape by posing its lattice (the pose tool's "Pose as rest shape"): the mesh
/// takes the shape the posed lattice gives it and the lattice returns to rest around it, so the body rests,
/// wobbles and exports in the new shape, as Blender's "apply lattice". An edit is kept as the lattice it was
/// made on and its posed nodes: a project stores its edits exactly, in a few hundred numbers, and replays
/// them over the mesh file (which stays untouched) on load.

#include "core/scene/scene.h"

#include <span>
#include <vector>

namespace softtouch {

/// One rest-shape edit: a lattice and the pose of its nodes that shaped the mesh.
struct RestShapeEdit {
    LatticeShape shape;         ///< Kind and resolution of the lattice the pose was made on.
    OrientedBox box;            ///< Its box (scene coordinates, metres).
    std::vector<Vec3> nodes;    ///< The posed node positions, one per node of `shape`, metres.
    /// Checks the shape and box, the node count and that every node is finite and within
    /// ranges::kMaxMeshSize of the origin.
    Status validate() const;
};

/// Applies an edit to a mesh: its positions and normals become those the posed lattice maps them to
/// (normals through the map's Jacobian, as every deformed frame's). Triangles and parts are kept.
Status applyRestShapeEdit(Mesh& mesh, const RestShapeEdit& edit);

/// `box` grown along its own axes just enough to hold every point, with `padding` × its largest side of
/// room on each side it had to grow; the same box when every point is inside.
OrientedBox boxHolding(const OrientedBox& box, std::span<const Vec3f> points, double padding = 0.02);

/// An object whose rest shape is `pose` (its lattice's nodes), and the edit that made it.
struct RestShapeChange {
    SceneObject object;  ///< The mesh in the posed shape; the lattice (same shape, material kept) around it.
    RestShapeEdit edit;  ///< What to store to make the same change again on load.
};

/// Makes `pose` the object's rest shape. Fails for an object that follows its own animation (its rest
/// shape is the animation's), a pose of another node count, or non-finite nodes.
Result<RestShapeChange> withRestShape(const SceneObject& object, std::span<const Vec3> pose);

}  // namespace softtouch
