#pragma once
/// Vertex-cache exporters (PC2, MDD, OBJ sequence) behind one streaming interface: one frame in
/// memory at a time, non-finite frames refused, the output published atomically by finish().
/// Byte layouts: docs/formats.md.

#include "core/base/result.h"
#include "core/geometry/mesh.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace softtouch::io {

/// The plain vertex caches: positions per frame (VertexCacheWriter). Every export, these included, is
/// listed and made through the export registry (io/export/export_formats.h). Layouts: docs/formats.md.
enum class CacheFormat {
    Pc2,          ///< 3ds Max point cache.
    Mdd,          ///< LightWave/Blender MDD.
    ObjSequence,  ///< One OBJ per frame.
};

/// "pc2", "mdd", "objseq": the export registry's names for them.
std::string_view cacheFormatName(CacheFormat format);
/// Parses a name written by cacheFormatName() (case-insensitive).
std::optional<CacheFormat> parseCacheFormat(std::string_view name);
/// From the file extension (.pc2, .mdd, .obj).
std::optional<CacheFormat> cacheFormatFromPath(const std::filesystem::path& path);

/// What a cache holds.
struct CacheInfo {
    std::size_t pointCount = 0;  ///< Vertices per frame, > 0.
    std::size_t frameCount = 0;  ///< Frames, > 0.
    double fps = 24.0;           ///< Frames per second, > 0.
    double startFrame = 0.0;     ///< Frame number of the first sample.
};

/// Streaming writer of one cache.
class VertexCacheWriter {
public:
    virtual ~VertexCacheWriter() = default;
    /// Starts writing `path`; nothing is visible there until finish().
    virtual Status begin(const std::filesystem::path& path, const CacheInfo& info) = 0;
    /// Appends one frame of exactly info.pointCount positions; refuses non-finite values.
    virtual Status writeFrame(std::span<const Vec3f> positions) = 0;
    /// Checks that every announced frame was written and publishes the file(s) atomically.
    virtual Status finish() = 0;
    /// Drops everything written so far; the previous file(s) stay untouched.
    virtual void abort() = 0;
};

/// A writer for a vertex cache. OBJ sequences need the rest mesh's triangles (written into every frame).
std::unique_ptr<VertexCacheWriter> makeCacheWriter(CacheFormat format, const Mesh& restMesh);

/// A cache read back (tests, round trips, tools).
struct VertexCache {
    CacheInfo info;
    std::vector<std::vector<Vec3f>> frames;
};
/// Reads a PC2 file; errors name the file and what is wrong (bad signature, truncated, …). PC2 stores
/// no frame rate (its "sampleRate" is a frame step), so info.fps is 0, meaning unknown.
Result<VertexCache> readPc2(const std::filesystem::path& path);
/// Reads an MDD file; MDD stores no fps, so info.fps comes from the frame times when there are two
/// (0, meaning unknown, for a single frame).
Result<VertexCache> readMdd(const std::filesystem::path& path);

/// Paths of an OBJ sequence written for `path` (dir/name.obj -> dir/name_0000.obj, …).
std::filesystem::path objSequenceFramePath(const std::filesystem::path& path, std::size_t frame);
/// Whether `fileName` names a frame, any frame, of the OBJ sequence written for `path` ("name_0007.obj",
/// "name_12345.obj"): what a re-run sweeps of a killed longer run.
bool isObjSequenceFrameName(const std::filesystem::path& path, const std::string& fileName);

/// Writes a mesh as Wavefront OBJ (v, vn, f), atomically. `positions`/`normals` override the mesh's own when
/// non-empty. No groups unless `groups`: then a "g NAME" line before the faces of each of the mesh's parts (a
/// face belongs to the part of its first vertex; parts in vertex order). Without groups the vertex order
/// survives any importer that keeps OBJ order; with them some importers split and reorder.
Status writeObj(const std::filesystem::path& path, const Mesh& mesh, std::span<const Vec3f> positions = {},
                std::span<const Vec3f> normals = {}, bool groups = false);

namespace detail {
/// The "g NAME" line that starts part `part` of `parts` when triangle `triangle` (its first vertex) enters it,
/// appended to `text`; `current` is the part of the previous triangle (-1 before the first).
void appendObjGroup(std::string& text, const std::vector<MeshPart>& parts, const std::array<std::uint32_t, 3>& triangle,
                    int& current);
}  // namespace detail

}  // namespace softtouch::io
