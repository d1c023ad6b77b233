#pragma once
/// Batch manifests (*.stbatch): a clip library described as scenes x material presets x clips x
/// formats, expanded into independent jobs, one per output, each with a stable id and a content hash
/// of everything it reads. A job's stamp (written after its files are published) records that hash, so
/// a re-run skips what is up to date. Running a job is the front end's (app/cli_batch.cpp): it needs the
/// renderer for video previews. Schema and the farm flow: docs/farm.md.

#include "core/base/result.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace softtouch::io {

/// Version of the manifest format written and read by this build.
constexpr int kBatchManifestVersion = 1;

/// What a farm task asks of the scheduler (Slurm's --cpus-per-task, --mem, --time, --partition).
struct BatchResources {
    int cpusPerTask = 1;     ///< Cores per job. [1, 256].
    int memoryMB = 2048;     ///< Memory per job, MiB. [64, 1048576].
    int minutes = 60;        ///< Wall-clock limit per job, minutes. [1, 10080].
    std::string partition;   ///< Slurm partition; empty: the cluster's default.
};

/// A loaded manifest; paths are absolute (relative ones are taken from the manifest's folder).
struct BatchManifest {
    std::filesystem::path path;                   ///< The manifest file.
    std::vector<std::filesystem::path> scenes;    ///< Projects (*.softtouch). At least one.
    std::vector<std::filesystem::path> presets;   ///< Material presets applied to every object; empty: the
                                                  ///< scenes as authored (one variant, named "as-authored").
    std::vector<std::string> clips;               ///< Clip names; empty: each scene's default clip.
    std::vector<std::string> formats;             ///< pc2, mdd, objseq, gltf, glb, pca, skin (GLB files, at bake's
                                                  ///< default error 0.5%), vat, lattice, mp4, gif.
    int frames = 0;                               ///< Frames per output; 0: the clip's. [0, 1e6].
    bool compress = false;                        ///< Pack the GLB outputs (glb, pca, skin) for shipping, as
                                                  ///< bake --compress.
    int videoWidth = 640, videoHeight = 360;      ///< Size of mp4/gif previews, pixels. [16, 8192], even.
    std::filesystem::path outputRoot;             ///< Folder of the library (default: "library" beside the manifest;
                                                  ///< the manifest may only name one inside its own folder,
                                                  ///< `batch --library DIR` any).
    std::string output = "{scene}/{preset}/{clip}-{format}"; ///< Path of each output under outputRoot, without
                                                  ///< extension: {scene}, {preset}, {clip}, {format}.
    BatchResources resources;                     ///< Per job, for farm scripts.
};

/// One output of the library and how to make it.
struct BatchJob {
    std::string id;                       ///< Stable: scene.preset.clip.format (letters, digits, '.', '-', '_').
    std::filesystem::path scene;          ///< Project to load.
    std::filesystem::path preset;         ///< Material preset to apply to every object; empty: none.
    std::string clip;                     ///< Clip to play; empty: the scene's default (or its drivers).
    std::string format;                   ///< One of BatchManifest::formats.
    int frames = 0;                       ///< As in the manifest.
    bool compress = false;                ///< A packed GLB (the manifest's compress, for a format that takes it).
    int videoWidth = 0, videoHeight = 0;  ///< For mp4/gif.
    std::filesystem::path output;         ///< The output's path (the --out a bake or render would get).
    std::vector<std::filesystem::path> inputs; ///< Every file it reads: scene, its meshes, the preset.
    std::uint64_t hash = 0;               ///< Of the job's settings and every input's bytes (FNV-1a, 64 bit).
};

/// Reads and checks a manifest (every problem names the file and the JSON pointer).
Result<BatchManifest> loadBatchManifest(const std::filesystem::path& path);

/// Called as a plan goes: jobs planned so far and the product's size (an upper bound when a scene's
/// default clip is used).
using BatchPlanProgress = std::function<void(std::size_t planned, std::size_t total)>;

/// Every problem of a manifest (each naming the file and the JSON pointer), then its plan's (a scene that
/// does not load, a clip a scene lacks, outputs that collide); empty when it plans, with the job count
/// in `jobs`. What `softtouch-cli validate` prints for a .stbatch.
std::vector<std::string> validateBatchManifest(const std::filesystem::path& path, std::size_t* jobs = nullptr);

/// Expands a manifest into its jobs, in a stable order (scene, preset, clip, format as listed). Loads
/// each scene to learn its meshes and clips: a named clip a scene lacks, two jobs that would write
/// the same file, an output outside outputRoot or a product of more than a million jobs fail the plan.
/// Each input file is read and hashed once, however many jobs read it.
Result<std::vector<BatchJob>> planBatch(const BatchManifest& manifest, const BatchPlanProgress& progress = {});

/// Where a job's stamp lives: outputRoot/.softtouch-batch/ID.json.
std::filesystem::path batchStampPath(const BatchManifest& manifest, const BatchJob& job);

/// True when the job's stamp records its current hash and every file it lists exists with the
/// recorded size (a job killed before its stamp was written is never up to date).
bool batchJobUpToDate(const BatchManifest& manifest, const BatchJob& job);

/// Records that `job` wrote `files` (written atomically, after the files themselves).
Status writeBatchStamp(const BatchManifest& manifest, const BatchJob& job,
                       const std::vector<std::filesystem::path>& files);

/// The files a job's stamp lists, or nothing when it has no valid stamp.
std::optional<std::vector<std::filesystem::path>> batchStampFiles(const BatchManifest& manifest, const BatchJob& job);

/// A scene's, preset's or clip's name as it goes into a library path ({scene}, {preset}, {clip}): ASCII
/// letters, digits, '.', '-' and '_' are kept, every other byte becomes '_' (a '/' or '\\' cannot make
/// folders, a control character cannot reach a script). A name of dots only ("..") is refused by the
/// reader and the plan, never written.
std::string libraryName(const std::string& text);

/// The hash as 16 hex digits.
std::string hashText(std::uint64_t hash);

/// True for the formats a job renders as video (mp4, gif); the others are exports of the registry
/// (io/export/export_formats.h).
bool isVideoFormat(std::string_view format);

}  // namespace softtouch::io
