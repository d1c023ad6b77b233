#pragma once
/// A clip turned into linear blend skinning with rigid bones, the path every game engine plays
/// cheaply: K bones, each with a rigid transform per frame, and at most four non-negative weights per
/// vertex summing to 1. Fitted as smooth skinning decomposition with rigid bones (Le & Deng, "Smooth
/// Skinning Decomposition with Rigid Bones", SIGGRAPH Asia 2012): bones are seeded by clustering the
/// vertices' trajectories, then weights (per vertex, a constrained least-squares fit over its best four
/// bones) and transforms (per bone and frame, a weighted Procrustes fit with the other bones held)
/// are improved in turn. Every step lowers the same squared error, so the fit only gets better.

#include "core/base/types.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace softtouch {

/// One bone's rigid transform at one frame: x' = rotation · x + translation (from the rest pose).
struct BoneTransform {
    Mat3 rotation = Mat3::Identity();
    Vec3 translation = Vec3::Zero();
};

/// The fitted skin.
struct SkinFit {
    int bones = 0;                                   ///< K.
    std::vector<std::array<std::uint16_t, 4>> joints;///< Per vertex, its four bones (unused slots repeat one with weight 0).
    std::vector<std::array<float, 4>> weights;       ///< Per vertex, ≥ 0, summing to 1.
    std::vector<std::vector<BoneTransform>> transforms; ///< [frame][bone].
    double rmsError = 0.0;                           ///< RMS vertex error over every vertex and frame, metres.
    double maxError = 0.0;                           ///< Largest vertex error in any frame, metres.
};

/// A skeleton the clip's mesh is already skinned to (a rig imported with it), in the terms linear blend skinning
/// needs: each joint's skinning transform (its world transform times its inverse bind matrix; affine, scale
/// allowed) at every frame, and each vertex's joints and weights.
struct SourceSkin {
    std::vector<std::vector<BoneTransform>> transforms; ///< [frame][joint], acting on the bind mesh.
    std::vector<std::array<std::uint16_t, 4>> joints;   ///< Per vertex, four joints (unused slots at weight 0).
    std::vector<std::array<float, 4>> weights;          ///< Per vertex, ≥ 0, summing to 1.
};

/// A skin on a source rig plus helper bones: skin.bones = J + H, where bones 0..J−1 are the source's joints
/// with their transforms unchanged and bones J.. are rigid helper bones fitted to what the rig does not do.
struct RigSkinFit {
    SkinFit skin;                    ///< Weights over source joints and helpers; errors measured with them.
    int sourceJoints = 0;            ///< J.
    std::vector<int> helperParent;   ///< Per helper, the source joint that weighs most where it acts.
    std::vector<Vec3> helperCentre;  ///< Per helper, its weighted centre on the bind mesh (where its bind pose sits).
};

/// Fits at most `helpers` rigid helper bones on top of `source` so that skinning by the source's joints and
/// the helpers reproduces `frames` (positions of the `bind` mesh's vertices). Only the helpers' transforms and
/// the weights change: the source joints keep their motion. Helpers are seeded where the source skin misses
/// most (k-means++ on the vertices' trajectories, a vertex the source carries well counting as covered), then
/// weights and helper transforms are improved in turn, each step never raising the error; a helper no vertex
/// ends up weighing is dropped, so fewer than `helpers` may come back (none when the rig alone is exact).
/// Deterministic.
RigSkinFit fitHelperBones(std::span<const Vec3f> bind, const std::vector<std::vector<Vec3f>>& frames,
                          const SourceSkin& source, int helpers, int iterations = 12);

/// Fits `bones` rigid bones to `frames` (each the deformed positions of the `rest` vertices), with
/// `iterations` rounds of weight and transform updates. Deterministic.
SkinFit fitRigidSkin(std::span<const Vec3f> rest, const std::vector<std::vector<Vec3f>>& frames, int bones,
                     int iterations = 12);

/// Sets the skin's rmsError and maxError against `frames` (what fitRigidSkin() reports, measured again after
/// the weights change, e.g. by roundSkinWeights()).
void measureSkinError(SkinFit& skin, std::span<const Vec3f> rest, const std::vector<std::vector<Vec3f>>& frames);

/// Rounds every vertex's weights to whole multiples of 1/steps that still sum to exactly 1 (largest
/// remainder), as a file stores them in `steps`-level normalized integers (255: the 8-bit weights engines
/// ship). The errors are not updated: call measureSkinError().
void roundSkinWeights(SkinFit& skin, int steps);

/// The skin's position of vertex i at frame f.
Vec3 skinnedPosition(const SkinFit& skin, std::span<const Vec3f> rest, std::size_t frame, std::size_t i);

}  // namespace softtouch
