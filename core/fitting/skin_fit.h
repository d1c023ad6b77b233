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
