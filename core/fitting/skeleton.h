#pragma once
/// A skeleton as a file brings it (joints, their hierarchy, bind pose and animation) and a mesh skinned to it:
/// what a skin export onto the source rig keeps untouched and fits helper bones on top of (skin_fit.h).

#include "core/fitting/skin_fit.h"

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace softtouch {

/// A node's local transform as files key it: x' = translation + rotation (scale ∘ x).
struct NodeTransform {
    Vec3 translation = Vec3::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  ///< Unit.
    Vec3 scale = Vec3::Ones();
    Eigen::Affine3d matrix() const;
};

/// The nodes a skin's joints hang from, evaluated at the frames of a clip.
struct Skeleton {
    struct Node {
        std::string name;        ///< As the file names it.
        int parent = -1;         ///< Index of its parent in `nodes`; −1 for a top-level node.
        NodeTransform rest;      ///< Its own transform in the file (what a player shows without the animation).
        bool animated = false;   ///< The take keys it.
    };
    std::vector<Node> nodes;                        ///< Joints and their ancestors, parents before children.
    std::vector<int> joints;                        ///< The skin's joints in skin order, as indices into `nodes`.
    std::vector<Eigen::Matrix4d> inverseBind;       ///< Per joint, metres.
    std::vector<std::vector<NodeTransform>> poses;  ///< [frame][node]: local transforms, metres.

    /// Every node's world transform at `frame` (parents' composed with its own).
    std::vector<Eigen::Affine3d> world(std::size_t frame) const;
};

/// A mesh skinned to a Skeleton: its bind-pose positions (what the inverse bind matrices undo) and at most
/// four joints (indices into Skeleton::joints) and weights a vertex.
struct SkinnedMesh {
    std::vector<Vec3f> bind;                           ///< Per vertex, metres, in the clip's vertex order.
    std::vector<std::array<std::uint16_t, 4>> joints;  ///< Per vertex.
    std::vector<std::array<float, 4>> weights;         ///< Per vertex, ≥ 0, summing to 1.
};

/// The skeleton a mesh came skinned to, as its file has it, and the mesh's skin on it.
struct SourceRig {
    Skeleton skeleton;    ///< Joints and their ancestors; poses at a clip's frames.
    SkinnedMesh mesh;     ///< Bind positions and weights.
    std::string meshName; ///< The skinned mesh's name in its file.
};

/// The skin `mesh` has on `skeleton` at each of its frames, as fitHelperBones() takes it: per frame and joint,
/// world × inverse bind.
SourceSkin sourceSkin(const Skeleton& skeleton, const SkinnedMesh& mesh);

}  // namespace softtouch
