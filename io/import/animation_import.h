#pragma once
/// Importing a mesh with its own animation through assimp (glTF/GLB, FBX, COLLADA, …): keyed node
/// transforms, skeletons with skinned meshes and morph-target (blend shape) weights, in any mix. The rig is
/// evaluated here, at a fixed rate over the chosen part of one take, into vertex positions (core's
/// BaseAnimation); the soft body adds its secondary motion on top (core/animation/base_motion.h).
///
/// Vertex order: every triangle mesh of the file, in the order the node hierarchy reaches them (depth
/// first), each as often as nodes instance it; the first sample is the object's rest mesh.

#include "core/animation/base_animation.h"
#include "core/base/ranges.h"
#include "core/fitting/skeleton.h"
#include "core/geometry/mesh.h"

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace softtouch::io {

/// How far into a take an import samples, seconds: the first hour, as far as a clip may start
/// (ranges::kMaxClipStart, which also bounds a project's "start" and "end" keys). A take whose length is not a
/// finite number is refused whatever part is asked for: its key times are not times.
inline constexpr double kMaxAnimationSeconds = ranges::kMaxClipStart;
/// Nodes of a rig (its joints, the meshes' nodes and any others) and joints one mesh is skinned to. A game
/// character has tens to a few hundred joints and a detailed face rig adds a few hundred more; ten thousand
/// leaves a margin of ten over the largest of them. Each costs every sample a transform.
inline constexpr std::size_t kMaxRigNodes = 10'000;
/// Vertex positions the samples may hold: 12 bytes each, 384 MiB, which the importer's child sends back
/// through a pipe (a minute at 120 samples/s of a 4,400-vertex character).
inline constexpr double kMaxSampledPositions = 32e6;
/// Rig operations an import may evaluate, summed over its samples: per sample, one per node, per vertex of
/// each placed mesh and its blend-shape targets, and per skin weight. A skinned mesh with four weights a
/// vertex reaches kMaxSampledPositions first; a rig with many blend shapes or weights meets this one.
inline constexpr double kMaxSampledOperations = 256e6;

/// Which part of which take to sample.
struct AnimationRequest {
    std::string take;      ///< The take's name; empty: the file's first take.
    double start = 0.0;    ///< Seconds into the take, [0, kMaxAnimationSeconds).
    double end = -1.0;     ///< Seconds into the take, (start, kMaxAnimationSeconds]; negative: the take's end.
    double rate = 120.0;   ///< Samples per second, [1, 1000] (bake frame rates that divide it land on samples).
    bool loop = true;      ///< The take repeats: the range's end runs on into its start.
};

/// A file's takes in file order: each one's name and length, seconds.
using TakeList = std::vector<std::pair<std::string, double>>;

/// What the import found.
struct AnimatedMesh {
    Mesh mesh;                       ///< The first sample, metres, with normals: the object's rest mesh.
    BaseAnimation animation;         ///< Every sample, metres.
    TakeList takes;                  ///< Every take of the file and its length, seconds.
    std::string unit;                ///< The unit the file was read in and why ("centimetres (FBX UnitScaleFactor 1)").
};

/// Imports `path` and samples `request`. Errors name the file and what is wrong: no animation, an unknown
/// take (listing the file's takes), a range outside the take or past kMaxAnimationSeconds, a take whose length
/// is not finite, a rig above kMaxRigNodes, samples above kMaxSampledPositions or kMaxSampledOperations. All
/// of these are refused, with the limit named, before anything is sampled.
Result<AnimatedMesh> importAnimatedMesh(const std::filesystem::path& path, const AnimationRequest& request);

/// The takes of `path` without sampling any (the editor's take chooser lists them before the import). Fails as
/// importAnimatedMesh() does on a file it cannot read or one with no animation.
Result<TakeList> animationTakes(const std::filesystem::path& path);

/// Reads the skeleton of `path`'s skinned mesh and evaluates take `take` (empty: the first) at each of
/// `takeSeconds`, in metres as importAnimatedMesh() reads the same file, vertices in its order. Fails, naming
/// the file, where the file does not place exactly one triangle mesh or that mesh is not skinned.
Result<SourceRig> importSourceRig(const std::filesystem::path& path, const std::string& take,
                                  const std::vector<double>& takeSeconds);

}  // namespace softtouch::io
