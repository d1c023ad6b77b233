#pragma once
/// Baking: play a scene frame by frame (a clip of its library, or its drivers simulated from rest)
/// and stream every frame into a vertex cache or clip export, with the rest mesh the cache matches
/// written beside it. One frame in memory at a time; nothing is written unless everything
/// succeeded; no non-finite frame ever reaches a file.

#include "core/authoring/clip.h"
#include "core/scene/scene.h"
#include "io/documents/project_file.h"
#include "io/export/clip_writer.h"
#include "io/export/export_formats.h"
#include "io/export/vertex_cache.h"

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace softtouch::io {

/// The file an object's mesh and base animation were read from, for a skin export onto the file's own rig.
struct MeshSource {
    std::filesystem::path file;         ///< Empty: none (a built-in shape, or a mesh whose rest shape was edited).
    Vec3 offset = Vec3::Zero();         ///< Metres the mesh was moved by on load ("position").
};

/// Per object of `project`, the file its mesh came from: its reference resolved against the project's folder.
/// An object whose rest shape was edited gets none: its mesh is no longer the file's.
std::vector<MeshSource> meshSources(const Project& project);

/// What to bake.
struct BakeOptions {
    std::filesystem::path output;           ///< Cache file (OBJ sequence: dir/name.obj; vat, lattice: a base path).
    const ExportFormat* format = findExportFormat("pc2");  ///< The export (io/export/export_formats.h); never null.
    ClipExportOptions exportOptions;        ///< Settings of the glTF, VAT and lattice exports.
    int frames = 0;                         ///< Frames to write; 0 takes the clip's (or the scene's) length.
                                            ///< More frames than a clip has: a loop clip cycles, others hold
                                            ///< their last frame.
    double fps = 0.0;                       ///< Frame rate; 0 takes the scene's. Must be 0 or the clip's for a clip.
    const ClipLibrary* clips = nullptr;     ///< The project's clip library; nullptr: the drivers from frame 0.
    std::string clip;                       ///< Clip of `clips` to bake; empty: the library's default clip, or
                                            ///< the drivers from frame 0 when it has none.
    int threads = 0;                        ///< Deformation threads; 0 uses every hardware thread.
    /// The objects whose meshes go into the cache, by name, in scene order; empty: every object. The whole
    /// scene is still simulated (objects may touch), only these are written.
    std::vector<std::string> objects;
    /// OBJ output (the rest mesh, an OBJ sequence's frames): a "g NAME" line before each object's faces, so a
    /// DCC imports one named part per object. Off by default: importers that split groups into meshes may
    /// weld or reorder vertices, which breaks the vertex order PC2 and MDD caches rely on.
    bool objectGroups = false;
    /// Per scene object, the file its mesh came from (meshSources()); a skin export (ClipExportOptions::skinRig)
    /// reads the skeleton there. Empty: not known, the skin export fits its own bones.
    std::vector<MeshSource> meshSources;
    /// Called after each frame with (frames done, total); returning false cancels the bake.
    std::function<bool(int, int)> progress;
    /// A clip of the library is simulated whole before its first frame is written: called with the fraction
    /// simulated before each of its frames; returning false cancels the bake.
    std::function<bool(double)> simulating;
};

/// What a bake wrote.
struct BakeResult {
    std::filesystem::path cache;     ///< The cache (for an OBJ sequence: the first frame; vat, lattice: the first file).
    std::vector<std::filesystem::path> files; ///< Every file the export wrote (exportFiles()), rest mesh excluded.
    std::filesystem::path restMesh;  ///< The OBJ whose vertex order the cache follows.
    int frames = 0;                  ///< Frames written.
    int objects = 0;                 ///< Objects in the scene.
    int meshEvaluations = 0;         ///< Object meshes deformed: an object whose nodes did not move since the
                                     ///< last frame (asleep, or a held clip frame) keeps its mesh, at no cost.
    std::size_t points = 0;          ///< Vertices per frame.
    std::vector<std::string> warnings; ///< Guard reports from the simulation (rolled-back steps, …) and the exporter's (engine limits).
    std::vector<std::string> notes;    ///< What the exporter measured of its output (ClipWriter::notes()).
    std::string clip;                ///< The clip baked; empty for the drivers from frame 0.
    std::optional<SeamMeasure> seam; ///< For a loop clip: its seam, measured on the lattice nodes.
};

/// Plays `scene` (io/pipeline/frame_source.h) and writes the cache or export and the rest mesh.
Result<BakeResult> bake(const Scene& scene, const BakeOptions& options);

/// Appends an object's mesh to the rest mesh a bake writes (its vertices, its normals where it has them, its
/// triangles renumbered): objects appended in scene order give the cache's vertex order. Returns the first
/// vertex's index. The caller computes normals once all are in, where some object had none.
std::uint32_t appendToRestMesh(Mesh& rest, const Mesh& object);

/// Where object `name`'s own cache goes when each object is baked to its own: "-NAME" added to the file's
/// stem (to a base path that has no extension), the name's characters other than letters, digits, '-' and
/// '_' written as '_'.
std::filesystem::path perObjectPath(const std::filesystem::path& output, const std::string& name);

/// One cache per object (perObjectPath()), each baked as bake() with only that object written; in scene order.
/// Stops at the first failure (the caches written before it stay, each complete).
Result<std::vector<BakeResult>> bakeEachObject(const Scene& scene, const BakeOptions& options);

}  // namespace softtouch::io
