// OBJ sequence: one Wavefront OBJ per frame, dir/name.obj -> dir/name_0000.obj, name_0001.obj, …
// Each file holds the frame's positions ("v") and the rest mesh's triangles ("f"), in the vertex
// order of the rest mesh, with no groups (see writeObj()) unless the rest mesh it is made from names parts
// (a bake with object groups: "g NAME" before each object's faces).
//
// Publishing: a sequence is many files and no file system renames many files atomically. Each frame
// is therefore written completely beside its final name ("staged", itself through AtomicFile so a
// staged frame is flushed and synced), and finish() renames the staged frames onto their final
// names only once every announced frame was written. A failed or aborted export removes the staged
// frames and leaves every existing frame file untouched.

#include "io/export/vertex_cache.h"

#include "io/export/clip_writer_internal.h"
#include "io/export/vertex_cache_internal.h"
#include "io/files/atomic_file.h"

#include <algorithm>
#include <optional>
#include <string>
#include <system_error>

namespace softtouch::io {

namespace {

/// AtomicFile names the file it writes, which for a staged frame is "name_0000.obj.tmp-…"; a person
/// should read the frame's own name instead.
Status namingFrame(const Status& status, const std::filesystem::path& staged,
                   const std::filesystem::path& frame) {
    if (status)
        return status;
    std::string message = status.message();
    const std::string stagedName = detail::quoted(staged);
    if (const std::size_t at = message.find(stagedName); at != std::string::npos)
        message.replace(at, stagedName.size(), detail::quoted(frame));
    return Status::error(std::move(message));
}

class ObjSequenceWriter final : public VertexCacheWriter {
public:
    ObjSequenceWriter(std::vector<std::array<std::uint32_t, 3>> triangles, std::vector<MeshPart> groups)
        : m_triangles(std::move(triangles)), m_groups(std::move(groups)) {}
    ~ObjSequenceWriter() override { abort(); }
    ObjSequenceWriter(const ObjSequenceWriter&) = delete;
    ObjSequenceWriter& operator=(const ObjSequenceWriter&) = delete;

    Status begin(const std::filesystem::path& path, const CacheInfo& info) override {
        abort();  // a writer may be reused; whatever it was doing is dropped
        if (Status s = detail::checkCacheInfo(path, info); !s)
            return s;
        for (std::size_t t = 0; t < m_triangles.size(); ++t) {
            for (std::uint32_t index : m_triangles[t]) {
                if (index >= info.pointCount)
                    return Status::error("cannot write " + detail::quoted(path) + ": triangle " +
                                         std::to_string(t) + " of the rest mesh uses vertex " +
                                         std::to_string(index) + " but frames have " +
                                         std::to_string(info.pointCount) + " vertices");
            }
        }
        m_path = path;
        m_info = info;
        m_active = true;
        // Open the first frame now so that an unwritable directory is reported by begin(), as the
        // single-file writers do.
        if (Status s = openNextFrame(); !s) {
            abort();
            return s;
        }
        return Status::success();
    }

    Status writeFrame(std::span<const Vec3f> positions) override {
        if (!m_active)
            return Status::error(
                "no vertex cache is being written: begin() was not called or the write failed");
        const std::size_t frame = m_staged.size();
        if (Status s = detail::checkFrame(m_path, frame, m_info, positions); !s) {
            abort();
            return s;
        }
        m_text.clear();  // keeps its capacity: one frame's text is allocated once per export
        m_text += "# SoftTouch vertex cache: frame " + std::to_string(frame) + " of " +
                  std::to_string(m_info.frameCount) + ", vertex order of the rest mesh\n";
        for (const Vec3f& p : positions)
            detail::appendObjVector(m_text, "v", p);
        int part = -1;
        for (const auto& triangle : m_triangles) {
            if (!m_groups.empty())
                detail::appendObjGroup(m_text, m_groups, triangle, part);
            detail::appendObjFace(m_text, triangle, false);
        }
        Status s = m_current->write(m_text.data(), m_text.size());
        if (s)
            s = m_current->commit();
        if (!s) {
            s = namingFrame(s, m_current->target(), objSequenceFramePath(m_path, frame));
            abort();
            return s;
        }
        m_staged.push_back(m_current->target());
        m_current.reset();
        if (m_staged.size() < m_info.frameCount) {
            if (Status next = openNextFrame(); !next) {
                abort();
                return next;
            }
        }
        return Status::success();
    }

    Status finish() override {
        if (!m_active)
            return Status::error(
                "no vertex cache is being written: begin() was not called or the write failed");
        if (m_staged.size() != m_info.frameCount) {
            Status s = detail::frameCountMismatch(m_path, m_staged.size(), m_info.frameCount);
            abort();
            return s;
        }
        for (std::size_t frame = 0; frame < m_staged.size(); ++frame) {
            const std::filesystem::path target = objSequenceFramePath(m_path, frame);
            std::error_code error;
            std::filesystem::rename(m_staged[frame], target, error);
            if (!error)
                detail::forgetTemporary(m_staged[frame]);
            if (error) {
                // Renames within one directory practically never fail once the files exist; if one
                // does, frames before it are already replaced and cannot be put back.
                m_staged.erase(m_staged.begin(), m_staged.begin() + std::ptrdiff_t(frame));
                abort();
                const std::string replaced =
                    frame == 0 ? std::string("no frame was replaced")
                               : "frames 0 to " + std::to_string(frame - 1) + " are already the new ones";
                return Status::error("cannot replace " + detail::quoted(target) + ": " + error.message() +
                                     "; " + replaced);
            }
        }
        m_staged.clear();
        m_active = false;
        return Status::success();
    }

    void abort() override {
        m_current.reset();  // AtomicFile's destructor removes its temporary
        for (const std::filesystem::path& staged : m_staged) {
            std::error_code ignored;
            std::filesystem::remove(staged, ignored);
            detail::forgetTemporary(staged);
        }
        m_staged.clear();
        m_text.clear();
        m_text.shrink_to_fit();
        m_active = false;
    }

private:
    Status openNextFrame() {
        // The staged name carries ".tmp-" like every temporary, so leftovers of a crash are recognisable.
        const std::filesystem::path frame = objSequenceFramePath(m_path, m_staged.size());
        m_current.emplace(detail::temporaryPathFor(frame));
        Status s = m_current->open();
        if (!s) {
            s = namingFrame(s, m_current->target(), frame);
            m_current.reset();
        }
        return s;
    }

    std::vector<std::array<std::uint32_t, 3>> m_triangles;  ///< The rest mesh's, written into every frame.
    std::vector<MeshPart> m_groups;  ///< Parts named as OBJ groups in every frame (empty: no groups).
    std::filesystem::path m_path;                          ///< The sequence's base path (dir/name.obj).
    CacheInfo m_info;                                      ///< What begin() announced.
    bool m_active = false;                                 ///< Between begin() and finish()/abort().
    std::optional<AtomicFile> m_current;                   ///< The next frame's staged file, open.
    std::vector<std::filesystem::path> m_staged;           ///< Frames written completely, in order.
    std::string m_text;                                    ///< One frame's text: one frame in memory.
};

}  // namespace

namespace detail {

std::unique_ptr<VertexCacheWriter> makeObjSequenceWriter(const Mesh& restMesh) {
    return std::make_unique<ObjSequenceWriter>(restMesh.triangles, restMesh.parts);
}

/// The "objseq" export (io/export/export_formats.cpp): the rest mesh's triangles in every frame.
std::unique_ptr<ClipWriter> makeObjSequenceExport(const std::filesystem::path&, const ClipExportOptions&) {
    return makeVertexCacheClipWriter(makeObjSequenceWriter);
}

/// Every frame's file, the first one first.
std::vector<std::filesystem::path> objSequenceFiles(const std::filesystem::path& path, std::size_t frames) {
    std::vector<std::filesystem::path> files;
    for (std::size_t f = 0; f < std::max<std::size_t>(frames, 1); ++f)
        files.push_back(objSequenceFramePath(path, f));
    return files;
}

}  // namespace detail

}  // namespace softtouch::io
