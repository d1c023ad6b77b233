#include "io/export/vertex_cache.h"

#include "io/export/export_formats.h"
#include "io/export/vertex_cache_internal.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>
#include <system_error>
#include <utility>

#include <sys/stat.h>

namespace softtouch::io {

namespace {

constexpr std::array<std::pair<CacheFormat, std::string_view>, 3> kCacheNames = {
    {{CacheFormat::Pc2, "pc2"}, {CacheFormat::Mdd, "mdd"}, {CacheFormat::ObjSequence, "objseq"}}};

}  // namespace

std::string_view cacheFormatName(CacheFormat format) {
    for (const auto& [kind, name] : kCacheNames)
        if (kind == format)
            return name;
    return "pc2";  // unreachable: every enumerator is listed
}

std::optional<CacheFormat> parseCacheFormat(std::string_view name) {
    // The registry's lookup, case-insensitive as people type names; pc2, mdd and objseq are its entries.
    if (const ExportFormat* f = findExportFormat(name))
        for (const auto& [kind, listed] : kCacheNames)
            if (listed == f->name)
                return kind;
    return std::nullopt;
}

std::optional<CacheFormat> cacheFormatFromPath(const std::filesystem::path& path) {
    // The registry's extensions: .obj is objseq, the others each name their format.
    if (const ExportFormat* f = exportFormatForPath(path))
        return parseCacheFormat(f->name);
    return std::nullopt;
}

std::unique_ptr<VertexCacheWriter> makeCacheWriter(CacheFormat format, const Mesh& restMesh) {
    switch (format) {
    case CacheFormat::Pc2:
        return detail::makePc2Writer();
    case CacheFormat::Mdd:
        return detail::makeMddWriter();
    case CacheFormat::ObjSequence:
        return detail::makeObjSequenceWriter(restMesh);
    }
    return nullptr;  // unreachable: every enumerator is handled above
}

namespace {

/// What comes before and after the frame number in an OBJ sequence's file names.
std::pair<std::string, std::string> objSequenceNameParts(const std::filesystem::path& path) {
    return {path.stem().string() + "_", path.has_extension() ? path.extension().string() : std::string(".obj")};
}

}  // namespace

std::filesystem::path objSequenceFramePath(const std::filesystem::path& path, std::size_t frame) {
    // Four digits at least so that names sort in frame order in a file browser and match the
    // "name_####" pattern importers look for; more digits rather than wrapping past 9999.
    std::string number = std::to_string(frame);
    if (number.size() < 4)
        number.insert(0, 4 - number.size(), '0');
    const auto [before, after] = objSequenceNameParts(path);
    return path.parent_path() / (before + number + after);
}

bool isObjSequenceFrameName(const std::filesystem::path& path, const std::string& fileName) {
    const auto [before, after] = objSequenceNameParts(path);
    if (fileName.size() < before.size() + 4 + after.size() || !fileName.starts_with(before) || !fileName.ends_with(after))
        return false;
    const std::string number = fileName.substr(before.size(), fileName.size() - before.size() - after.size());
    return number.find_first_not_of("0123456789") == std::string::npos;
}

namespace detail {

Status checkCacheInfo(const std::filesystem::path& path, const CacheInfo& info) {
    const std::string prefix = "cannot write " + quoted(path) + ": ";
    if (info.pointCount == 0)
        return Status::error(prefix + "a vertex cache needs at least one vertex per frame");
    if (info.frameCount == 0)
        return Status::error(prefix + "a vertex cache needs at least one frame");
    if (!std::isfinite(info.fps) || info.fps <= 0.0)
        return Status::error(prefix + "the frame rate must be a finite number above 0 fps, got " +
                             formatNumber(info.fps));
    if (!std::isfinite(info.startFrame))
        return Status::error(prefix + "the start frame must be finite, got " + formatNumber(info.startFrame));
    return Status::success();
}

Status checkFrame(const std::filesystem::path& path, std::size_t frameIndex, const CacheInfo& info,
                  std::span<const Vec3f> positions) {
    const std::string nothingWritten = "; nothing was written to " + quoted(path);
    const std::string frame = "frame " + std::to_string(frameIndex);
    if (frameIndex >= info.frameCount)
        return Status::error(frame + " is one more than the " + std::to_string(info.frameCount) +
                             " frames announced" + nothingWritten);
    if (positions.size() != info.pointCount)
        return Status::error(frame + " has " + std::to_string(positions.size()) +
                             " vertices, the cache has " + std::to_string(info.pointCount) + " per frame" +
                             nothingWritten);
    const auto bad =
        std::find_if(positions.begin(), positions.end(), [](const Vec3f& p) { return !isFinite(p); });
    if (bad != positions.end())
        return Status::error(frame + " vertex " + std::to_string(bad - positions.begin()) + " is not finite" +
                             nothingWritten);
    return Status::success();
}

Status frameCountMismatch(const std::filesystem::path& path, std::size_t written, std::size_t announced) {
    return Status::error("cannot write " + quoted(path) + ": " + std::to_string(written) + " of the " +
                         std::to_string(announced) + " announced frames were written; nothing was written");
}

Status SingleFileCacheWriter::begin(const std::filesystem::path& path, const CacheInfo& info) {
    abort();  // a writer may be reused; whatever it was doing is dropped
    if (Status s = checkCacheInfo(path, info); !s)
        return s;
    std::vector<std::uint8_t> header;
    if (Status s = encodeHeader(path, info, header); !s)
        return s;
    m_file.emplace(path);
    if (Status s = m_file->open(); !s) {
        m_file.reset();
        return s;
    }
    if (Status s = m_file->write(header.data(), header.size()); !s) {
        m_file.reset();
        return s;
    }
    m_path = path;
    m_info = info;
    m_framesWritten = 0;
    return Status::success();
}

Status SingleFileCacheWriter::writeFrame(std::span<const Vec3f> positions) {
    if (!m_file)
        return Status::error("no vertex cache is being written: begin() was not called or the write failed");
    if (Status s = checkFrame(m_path, m_framesWritten, m_info, positions); !s) {
        abort();
        return s;
    }
    m_buffer.clear();
    encodeFrame(positions, m_buffer);
    if (Status s = m_file->write(m_buffer.data(), m_buffer.size()); !s) {
        abort();
        return s;
    }
    ++m_framesWritten;
    return Status::success();
}

Status SingleFileCacheWriter::finish() {
    if (!m_file)
        return Status::error("no vertex cache is being written: begin() was not called or the write failed");
    if (m_framesWritten != m_info.frameCount) {
        Status s = frameCountMismatch(m_path, m_framesWritten, m_info.frameCount);
        abort();
        return s;
    }
    Status s = m_file->commit();
    m_file.reset();
    m_framesWritten = 0;
    return s;
}

void SingleFileCacheWriter::abort() {
    m_file.reset();  // AtomicFile's destructor removes the temporary
    m_framesWritten = 0;
    m_buffer.clear();
    m_buffer.shrink_to_fit();
}

InputFile::InputFile(std::filesystem::path path) : m_path(std::move(path)) {}

InputFile::~InputFile() {
    if (m_file != nullptr)
        std::fclose(m_file);
}

Status InputFile::open() {
    errno = 0;
    m_file = std::fopen(m_path.c_str(), "rb");
    if (m_file == nullptr)
        return Status::error("cannot read " + quoted(m_path) + ": " + std::generic_category().message(errno));
    struct stat info {};
    if (::fstat(::fileno(m_file), &info) != 0)
        return Status::error("cannot read " + quoted(m_path) + ": " + std::generic_category().message(errno));
    if (!S_ISREG(info.st_mode))
        return Status::error("cannot read " + quoted(m_path) + ": not a regular file");
    m_size = static_cast<std::uint64_t>(info.st_size);
    return Status::success();
}

Status InputFile::read(void* data, std::size_t size) {
    errno = 0;
    if (std::fread(data, 1, size, m_file) != size) {
        const int error = errno;
        if (error == 0)
            return Status::error(quoted(m_path) + " ended early: it changed while being read");
        return Status::error("cannot read " + quoted(m_path) + ": " + std::generic_category().message(error));
    }
    return Status::success();
}

Status sizeMismatch(const std::filesystem::path& path, const std::string& layout,
                    std::optional<std::uint64_t> expected, std::uint64_t actual) {
    if (!expected)
        return Status::error(quoted(path) + " is truncated: its header announces " + layout +
                             ", more than any file can hold, but the file has " + std::to_string(actual) +
                             " bytes");
    if (actual < *expected)
        return Status::error(quoted(path) + " is truncated: its header announces " + layout + " (" +
                             std::to_string(*expected) + " bytes) but the file has " + std::to_string(actual) +
                             " bytes");
    return Status::error(quoted(path) + " has " + std::to_string(actual - *expected) +
                         " extra bytes after the " + layout + " its header announces");
}

std::optional<std::uint64_t> checkedSize(std::uint64_t header, std::uint64_t count, std::uint64_t bytesEach) {
    constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
    if (bytesEach != 0 && count > (kMax - header) / bytesEach)
        return std::nullopt;
    return header + count * bytesEach;
}

}  // namespace detail

}  // namespace softtouch::io
