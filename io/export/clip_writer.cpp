#include "io/export/clip_writer.h"

#include "io/export/clip_writer_internal.h"
#include "io/export/vertex_cache_internal.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

namespace softtouch::io {

namespace {

/// A vertex cache (PC2, MDD, OBJ sequence) behind the clip interface: positions only.
class VertexCacheClipWriter final : public ClipWriter {
public:
    explicit VertexCacheClipWriter(detail::MakeVertexCacheWriter make) : m_make(make) {}

    Status begin(const std::filesystem::path& path, const ClipSetup& setup) override {
        abort();
        m_writer = m_make(setup.restMesh);
        return m_writer->begin(path, setup.info);
    }
    Status writeFrame(const FrameData& frame) override {
        if (!m_writer)
            return Status::error("no vertex cache is being written: begin() was not called");
        return m_writer->writeFrame(frame.positions);
    }
    Status finish() override {
        if (!m_writer)
            return Status::error("no vertex cache is being written: begin() was not called");
        return m_writer->finish();
    }
    void abort() override {
        if (m_writer)
            m_writer->abort();
    }

private:
    detail::MakeVertexCacheWriter m_make;
    std::unique_ptr<VertexCacheWriter> m_writer;
};

}  // namespace

std::unique_ptr<ClipWriter> detail::makeVertexCacheClipWriter(MakeVertexCacheWriter make) {
    return std::make_unique<VertexCacheClipWriter>(make);
}

Status checkFrameData(const std::filesystem::path& path, std::size_t frameIndex, const ClipSetup& setup,
                      const FrameData& frame, bool needNormals, bool needNodes) {
    if (Status s = detail::checkFrame(path, frameIndex, setup.info, frame.positions); !s)
        return s;
    const std::string nothingWritten = "; nothing was written to " + detail::quoted(path);
    const std::string name = "frame " + std::to_string(frameIndex);
    if (needNormals) {
        if (frame.normals.size() != setup.info.pointCount)
            return Status::error(name + " has " + std::to_string(frame.normals.size()) + " normals, expected " +
                                 std::to_string(setup.info.pointCount) + nothingWritten);
        const auto bad = std::find_if(frame.normals.begin(), frame.normals.end(),
                                      [](const Vec3f& n) { return !isFinite(n); });
        if (bad != frame.normals.end())
            return Status::error(name + " normal " + std::to_string(bad - frame.normals.begin()) +
                                 " is not finite" + nothingWritten);
    }
    if (needNodes) {
        if (frame.nodes.size() != setup.objects.size())
            return Status::error(name + " has lattice nodes for " + std::to_string(frame.nodes.size()) +
                                 " objects, expected " + std::to_string(setup.objects.size()) + nothingWritten);
        for (std::size_t o = 0; o < frame.nodes.size(); ++o) {
            const auto expected = std::size_t(setup.objects[o].lattice.nodeCount());
            if (frame.nodes[o].size() != expected)
                return Status::error(name + " object " + std::to_string(o) + " has " +
                                     std::to_string(frame.nodes[o].size()) + " lattice nodes, expected " +
                                     std::to_string(expected) + nothingWritten);
            for (std::size_t n = 0; n < expected; ++n) {
                if (!frame.nodes[o][n].allFinite())
                    return Status::error(name + " object " + std::to_string(o) + " lattice node " +
                                         std::to_string(n) + " is not finite" + nothingWritten);
            }
        }
    }
    return Status::success();
}

namespace detail {

StagedFile::StagedFile(std::filesystem::path target)
    : m_target(std::move(target)), m_temporary(temporaryPathFor(m_target)) {}

StagedFile::~StagedFile() { discard(); }

Status StagedFile::write(std::string_view bytes) {
    errno = 0;
    std::FILE* file = std::fopen(m_temporary.c_str(), "wb");
    if (file == nullptr)
        return Status::error("cannot write " + quoted(m_target) + ": " + std::generic_category().message(errno));
    const bool written = bytes.empty() || std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
    const int error = errno;
    if (std::fclose(file) != 0 || !written) {
        discard();
        return Status::error("cannot write " + quoted(m_target) + ": " +
                             std::generic_category().message(error != 0 ? error : EIO));
    }
    return Status::success();
}

Status StagedFile::publish() {
    // Sync what a library may have written by name before the rename (AtomicFile::commit's reason).
    const int fd = ::open(m_temporary.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return Status::error("cannot write " + quoted(m_target) + ": its staged data is missing (" +
                             std::generic_category().message(errno) + ")");
    const bool synced = ::fsync(fd) == 0 || errno == EINVAL;
    const int error = errno;
    ::close(fd);
    if (!synced)
        return Status::error("cannot write " + quoted(m_target) + ": " + std::generic_category().message(error));
    std::error_code renameError;
    std::filesystem::rename(m_temporary, m_target, renameError);
    if (renameError)
        return Status::error("cannot replace " + quoted(m_target) + ": " + renameError.message());
    forgetTemporary(m_temporary);
    m_published = true;
    return Status::success();
}

void StagedFile::discard() {
    if (m_published)
        return;
    std::error_code ignored;
    std::filesystem::remove(m_temporary, ignored);
    forgetTemporary(m_temporary);
}

Status publishAll(std::vector<std::unique_ptr<StagedFile>>& files) {
    std::string replaced;
    for (auto& file : files) {
        if (Status s = file->publish(); !s) {
            for (auto& rest : files)
                rest->discard();
            return Status::error(s.message() + (replaced.empty() ? std::string()
                                                                 : "; already replaced: " + replaced));
        }
        replaced += (replaced.empty() ? "" : ", ") + quoted(file->target());
    }
    files.clear();
    return Status::success();
}

Status checkWritable(const std::filesystem::path& target) {
    // Probe with a real temporary: access() lies for root and on read-only mounts.
    StagedFile probe(target);
    if (Status s = probe.write({}); !s)
        return s;
    probe.discard();
    return Status::success();
}

Status checkExportMemory(const std::filesystem::path& target, double bytes, const std::string& what) {
    if (bytes <= kMaxExportMemoryBytes)
        return Status::success();
    char text[64];
    std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
    return Status::error("cannot write " + quoted(target) + ": " + what + " holds the whole clip in memory, " + text +
                         " here, above the 8.6 GB limit; bake fewer frames, or use --format vat or lattice, which stream");
}

}  // namespace detail

}  // namespace softtouch::io
