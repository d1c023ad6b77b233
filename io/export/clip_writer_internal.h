#pragma once
/// Internals shared by the clip writers (clip_writer.cpp, gltf_export.cpp, vat_export.cpp,
/// lattice_cache.cpp). Not part of the io API: include it from io/*.cpp only.

#include "io/export/clip_writer.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tinygltf {
class Model;
struct Animation;
}

namespace softtouch::io::detail {

/// One output of a multi-file export, staged in a temporary file beside its target and renamed
/// over it by publish(). Destroying it unpublished removes the temporary, so an aborted export
/// leaves the previous files untouched and nothing behind.
class StagedFile {
public:
    explicit StagedFile(std::filesystem::path target);
    ~StagedFile();
    StagedFile(const StagedFile&) = delete;
    StagedFile& operator=(const StagedFile&) = delete;

    /// The file that publish() replaces.
    const std::filesystem::path& target() const { return m_target; }
    /// The temporary a library may write by name (OpenEXR); exists after a successful write or
    /// once the library created it.
    const std::filesystem::path& temporary() const { return m_temporary; }
    /// Writes `bytes` to the temporary; errors name the target.
    Status write(std::string_view bytes);
    /// Syncs the temporary and renames it over the target.
    Status publish();
    /// Removes the temporary.
    void discard();

private:
    std::filesystem::path m_target;
    std::filesystem::path m_temporary;
    bool m_published = false;
};

/// Publishes staged files in order; on the first failure, discards the rest and says which were
/// already replaced.
Status publishAll(std::vector<std::unique_ptr<StagedFile>>& files);

/// Checks that `target`'s folder exists and is writable before a long bake starts; names the file.
Status checkWritable(const std::filesystem::path& target);

/// Most memory an export that cannot stream (glTF keeps the whole clip until it is written) may plan
/// to hold: a longer clip is refused before the bake starts rather than exhausting memory at its end.
inline constexpr double kMaxExportMemoryBytes = 8.0 * 1024 * 1024 * 1024;
/// Refuses an export that would hold `bytes` in memory (named `what`), naming the file and the way out.
Status checkExportMemory(const std::filesystem::path& target, double bytes, const std::string& what);

// ---- glTF building (tinygltf) -------------------------------------------------------------------

/// Appends `values` (count elements of `components` floats each: 1, 2, 3 or 4) to buffer 0 as a
/// new buffer view + FLOAT accessor; with `bounds`, min/max are set (required for POSITION).
/// Returns the accessor index.
int addFloatAccessor(tinygltf::Model& model, const float* values, std::size_t count, int components,
                     bool vertexAttribute, bool bounds);
/// Keys of a clip's animation: one per frame, and one more closing a loop (ClipSetup::loops) at
/// frameCount / fps, which holds frame `key % frameCount`.
inline std::size_t animationKeys(const ClipSetup& setup) { return setup.info.frameCount + (setup.loops ? 1 : 0); }
/// Appends the key times, key f at f / fps (animationKeys() of them), as an animation input accessor, and
/// marks `animation` when the last key closes a loop (`"extras": {"loopClosingKey": true}`, so a reader that
/// counts keys as frames, the preview, knows it is frame 0 again, one frame on). Returns the accessor.
int addKeyTimes(tinygltf::Model& model, const ClipSetup& setup, tinygltf::Animation& animation);
/// Appends `byteCount` bytes, already laid out as glTF wants them (little-endian), as a new buffer view (with
/// `target` when non-zero; the buffer padded to 4 bytes after it) and an accessor of `count` elements of
/// `componentType` and `type` over it; returns the accessor's index. The other accessor writers go through it.
int addRawAccessor(tinygltf::Model& model, const void* bytes, std::size_t byteCount, std::size_t count, int componentType,
                   int type, int target);
/// Appends triangle indices as an index accessor, 16-bit where every index lies below 65535 (else 32-bit);
/// returns its index.
int addIndexAccessor(tinygltf::Model& model, std::span<const std::array<std::uint32_t, 3>> triangles,
                     std::uint32_t baseVertex);
/// Serialises the model as .gltf (buffer embedded as a data URI) or .glb; a .glb `compress`ed for shipping
/// (ClipExportOptions::gltfCompress, io/import/gltf_meshopt.h), with the largest change packing made to a morph-target
/// delta (metres) in `targetChange` when given.
Result<std::string> serializeGltf(const tinygltf::Model& model, bool binary, const std::filesystem::path& path,
                                  bool compress = false, double* targetChange = nullptr);
/// Refuses --compress for a glTF JSON path (the extension packs the GLB's binary chunk).
Status checkCompressible(const std::filesystem::path& path, bool binary, const ClipExportOptions& options);

// ---- Writers (each export's factory is declared with the registry, io/export/export_formats.cpp) ------------

/// Makes a vertex cache's writer for the rest mesh (an OBJ sequence writes its triangles into every frame).
using MakeVertexCacheWriter = std::unique_ptr<VertexCacheWriter> (*)(const Mesh& restMesh);
/// A vertex cache (PC2, MDD, OBJ sequence) behind the clip interface: positions only.
std::unique_ptr<ClipWriter> makeVertexCacheClipWriter(MakeVertexCacheWriter make);
/// glTF/GLB morph-target animation (gltf_export.cpp).
std::unique_ptr<ClipWriter> makeGltfWriter(bool binary, const ClipExportOptions& options);
/// The skinned glTF/GLB writer (ClipExportOptions::skinError or skinBones set; gltf_skin_export.cpp).
std::unique_ptr<ClipWriter> makeSkinWriter(bool binary, const ClipExportOptions& options);

}  // namespace softtouch::io::detail
