#pragma once
/// Baking: simulate a scene frame by frame and stream every frame into a vertex cache, with the
/// rest mesh the cache matches written beside it. One frame in memory at a time; nothing is written
/// unless everything succeeded; no non-finite frame ever reaches a file.

#include "core/clip.h"
#include "core/scene.h"
#include "io/vertex_cache.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace softtouch::io {

/// What to bake.
struct BakeOptions {
    std::filesystem::path output;           ///< Cache file (for an OBJ sequence: dir/name.obj).
    CacheFormat format = CacheFormat::Pc2;  ///< Cache format.
    int frames = 0;                         ///< Frames to write; 0 takes the clip's (or the scene's) length.
                                            ///< More frames than a clip has: a loop clip cycles, others hold
                                            ///< their last frame.
    double fps = 0.0;                       ///< Frame rate; 0 takes the scene's. Must be 0 or the clip's for a clip.
    const ClipLibrary* clips = nullptr;     ///< The project's clip library; nullptr: the drivers from frame 0.
    std::string clip;                       ///< Clip of `clips` to bake; empty: the library's default clip, or
                                            ///< the drivers from frame 0 when it has none.
    int threads = 0;                        ///< Deformation threads; 0 uses every hardware thread.
    /// Called after each frame with (frames done, total); returning false cancels the bake.
    std::function<bool(int, int)> progress;
};

/// What a bake wrote.
struct BakeResult {
    std::filesystem::path cache;     ///< The cache (for an OBJ sequence: the first frame).
    std::filesystem::path restMesh;  ///< The OBJ whose vertex order the cache follows.
    int frames = 0;                  ///< Frames written.
    std::size_t points = 0;          ///< Vertices per frame.
    std::vector<std::string> warnings; ///< Guard reports from the simulation (rolled-back steps, …).
    std::string clip;                ///< The clip baked; empty for the drivers from frame 0.
    std::optional<SeamMeasure> seam; ///< For a loop clip: its seam, measured on the lattice nodes.
};

/// Where the rest mesh of a cache goes: the cache path with extension .obj (an OBJ sequence's
/// --out path itself).
std::filesystem::path restMeshPath(const std::filesystem::path& cache, CacheFormat format);

/// Frame count and rate of a run: the requested values, or the scene's where 0 was asked for.
struct FrameTiming {
    int frames = 0;    ///< Frames, >= 1.
    double fps = 0.0;  ///< Frames per second, (0, 1000].
};

/// Resolves and checks a requested frame count and rate against the scene's defaults.
Result<FrameTiming> resolveFrameTiming(const Scene& scene, int frames, double fps);

/// The frame loop every frame-by-frame output shares (bake, video render): for f = 0..frames-1,
/// advances `simulation` to f / fps and calls `onFrame(f)`; stops at the first failure and returns it.
/// Simulation problems are appended to `warnings`.
Status simulateFrames(SceneSimulation& simulation, const FrameTiming& timing, std::vector<std::string>* warnings,
                      const std::function<Status(int frame)>& onFrame);

/// Simulates `scene` from its rest state (or evaluates a clip of `options.clips`) and writes the cache
/// and the rest mesh.
Result<BakeResult> bake(const Scene& scene, const BakeOptions& options);

}  // namespace softtouch::io
