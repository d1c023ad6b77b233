#pragma once
/// Clip exports behind one streaming interface that sees more than positions: the rest mesh with
/// normals and triangles, each object's lattice, and per frame the positions, the normals and the
/// lattice node positions. Vertex caches (PC2, MDD, OBJ sequence) are adapted onto it; glTF/GLB
/// morph animation, vertex animation textures and the lattice cache are written through it.
/// Every writer refuses non-finite frames and publishes its file(s) only in finish(); abort() or a
/// failure leaves the previous files untouched and no temporary behind. Layouts: docs/formats.md.

#include "core/base/result.h"
#include "core/fitting/skeleton.h"
#include "core/geometry/lattice.h"
#include "core/geometry/mesh.h"
#include "io/export/vertex_cache.h"

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace softtouch::io {

/// One object of a clip: where its vertices and triangles sit in the concatenated rest mesh, and
/// the lattice that deforms it.
struct ClipObject {
    std::string name;                 ///< Object name from the scene (may be empty).
    std::uint32_t firstVertex = 0;    ///< First vertex in ClipSetup::restMesh.
    std::uint32_t vertexCount = 0;    ///< Vertices of the object, > 0.
    std::uint32_t firstTriangle = 0;  ///< First triangle in ClipSetup::restMesh (its indices are global).
    std::uint32_t triangleCount = 0;  ///< Triangles of the object.
    Lattice lattice;                  ///< The object's lattice (shape, basis, rest box).
};

/// What a clip writer is told before the first frame.
struct ClipSetup {
    CacheInfo info;                   ///< Vertices per frame, frames, fps, start frame.
    Mesh restMesh;                    ///< All objects concatenated: positions, unit normals, triangles.
    std::vector<ClipObject> objects;  ///< In vertex order; their ranges tile restMesh.
    /// The frames are whole cycles of a loop: frame frameCount is frame 0 again. Formats that key time (glTF)
    /// close the loop with one more key at frameCount / fps holding frame 0, so a player that loops by the
    /// animation's length goes from the last frame to the first in one frame's time, not in none.
    bool loops = false;
    /// The skeleton the (one) object's mesh came skinned to, posed at every frame, when its file has one and the
    /// bake asks for it (ClipExportOptions::skinRig): the skin export keeps it and fits helper bones on top.
    std::shared_ptr<const SourceRig> sourceRig;
};

/// One frame handed to a clip writer.
struct FrameData {
    std::span<const Vec3f> positions;                ///< info.pointCount deformed positions (metres).
    std::span<const Vec3f> normals;                  ///< Unit normals, same count; may be empty unless needsNormals().
    std::vector<std::span<const Vec3>> nodes;        ///< Per object, its lattice's node positions (metres); may be empty unless needsNodes().
};

/// Per-format export settings (defaults are what the CLI writes).
struct ClipExportOptions {
    /// glTF/GLB: LINEAR weights between frames (smooth at any playback rate, at most 2 targets
    /// active) instead of STEP (one target active, frames held).
    bool gltfLinear = true;
    /// glTF/GLB: write NORMAL deltas in every morph target (doubles the target data).
    bool gltfNormals = true;
    /// VAT: widest texture, texels. A frame of more vertices wraps onto several rows. [1, 16384].
    int vatMaxWidth = 8192;
    /// glTF/GLB: 0 writes one morph target per frame (exact). Above 0, compressed morphs: the frames'
    /// mean displacement plus the fewest principal components (core/fitting/morph_basis.h) that keep every
    /// frame's RMS vertex error at or below this fraction of the rest mesh's bounding-box diagonal,
    /// with a weights animation. [0, 0.1].
    double gltfMorphError = 0.0;
    /// The error target `--format pca` and `--format skin` use when none is given (CLI, editor, batch):
    /// 0.5% of the rest mesh's diagonal.
    static constexpr double kDefaultCompressionError = 0.005;
    /// glTF/GLB compressed morphs: most components, besides the mean. [1, 255].
    int gltfMaxMorphs = 32;
    /// glTF/GLB skinned export (core/fitting/skin_fit.h) when above 0: the fewest of 8, 16, 32, 64 rigid bones whose
    /// RMS vertex error over the clip is at most this fraction of the rest mesh's diagonal. [0, 0.1].
    double skinError = 0.0;
    /// glTF/GLB skinned export with exactly this many bones when above 0 (overrides skinError). [0, 256].
    int skinBones = 0;
    /// Which bones a skinned export uses.
    enum class SkinRig {
        Auto,    ///< The source rig where the one object baked came skinned to a skeleton, fitted bones elsewhere.
        Source,  ///< The source rig, or fail saying why there is none.
        Fitted,  ///< Rigid bones fitted to the clip alone (skinBones, skinError).
    };
    SkinRig skinRig = SkinRig::Auto;
    /// On the source rig: the most helper bones added (the fewest of 0, 2, 4, 8, 16 up to it that meet
    /// skinError, or exactly this many tried when skinBones is set). [0, 256].
    static constexpr int kDefaultHelperBones = 16;
    /// GLB only: compress for shipping (io/import/gltf_meshopt.h): every buffer view through EXT_meshopt_compression,
    /// normals as 16-bit octahedral vectors; the skinned export also stores 8-bit joints and weights.
    bool gltfCompress = false;
};

/// Streaming writer of one clip export.
class ClipWriter {
public:
    virtual ~ClipWriter() = default;
    /// Starts writing at `path` (a file, or a base path for the multi-file formats); nothing is
    /// visible there until finish().
    virtual Status begin(const std::filesystem::path& path, const ClipSetup& setup) = 0;
    /// Appends one frame; refuses wrong sizes and non-finite values (then aborts).
    virtual Status writeFrame(const FrameData& frame) = 0;
    /// Checks that every announced frame was written and publishes the file(s).
    virtual Status finish() = 0;
    /// Drops everything written so far; the previous file(s) stay untouched.
    virtual void abort() = 0;
    /// True when writeFrame() needs FrameData::normals.
    virtual bool needsNormals() const { return false; }
    /// True when writeFrame() needs FrameData::nodes.
    virtual bool needsNodes() const { return false; }
    /// Things a person should know about the written files (engine limits, …), filled by begin()
    /// and finish().
    const std::vector<std::string>& warnings() const { return m_warnings; }
    /// What the writer measured of its output (a compression's error and size), filled by finish().
    const std::vector<std::string>& notes() const { return m_notes; }

protected:
    std::vector<std::string> m_warnings;  ///< See warnings().
    std::vector<std::string> m_notes;     ///< See notes().
};

/// Checks one frame against the setup (counts, finiteness of positions, normals and nodes);
/// messages name the frame, what is wrong and end in "nothing was written to '<path>'".
Status checkFrameData(const std::filesystem::path& path, std::size_t frameIndex, const ClipSetup& setup,
                      const FrameData& frame, bool needNormals, bool needNodes);

}  // namespace softtouch::io
