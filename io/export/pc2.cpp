// PC2 ("POINTCACHE2"), the point cache of 3ds Max, read by Blender's Mesh Cache modifier and most DCCs.
//
//   offset  size  field (little-endian)
//        0    12  char[12]  "POINTCACHE2\0"
//       12     4  int32     version, always 1
//       16     4  int32     numPoints
//       20     4  float32   startFrame   first sample's frame number
//       24     4  float32   sampleRate   frames from one sample to the next (NOT samples per second)
//       28     4  int32     numSamples
//       32     …  numSamples × numPoints × float32[3] (x, y, z)
//
// "sampleRate" is a frame step: Blender's reader maps scene frame f to sample (f - start) / rate, and
// 3ds Max writes 0.5 for two samples per frame. We write one sample per frame, so it is 1.0, and the
// cache holds no frames-per-second at all: readPc2() reports fps = 0 ("unknown").

#include "io/export/vertex_cache.h"

#include "io/export/clip_writer_internal.h"
#include "io/export/vertex_cache_internal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace softtouch::io {

namespace {

using detail::ByteOrder;

constexpr std::array<char, 12> kSignature = {'P', 'O', 'I', 'N', 'T', 'C', 'A', 'C', 'H', 'E', '2', '\0'};
constexpr std::int32_t kPc2Version = 1;
constexpr std::uint64_t kHeaderSize = 32;
constexpr std::uint64_t kPc2BytesPerPoint = 12;

class Pc2Writer final : public detail::SingleFileCacheWriter {
protected:
    Status encodeHeader(const std::filesystem::path& path, const CacheInfo& info,
                        std::vector<std::uint8_t>& out) const override {
        constexpr auto kMaxCount = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
        if (info.pointCount > kMaxCount || info.frameCount > kMaxCount)
            return Status::error("cannot write " + detail::quoted(path) + ": PC2 stores at most " +
                                 std::to_string(kMaxCount) + " points and samples");
        // Checked here rather than cast blindly: a double beyond float's range has no float value.
        if (std::abs(info.startFrame) > std::numeric_limits<float>::max())
            return Status::error("cannot write " + detail::quoted(path) + ": the start frame " +
                                 detail::formatNumber(info.startFrame) + " does not fit PC2's float32");
        out.insert(out.end(), kSignature.begin(), kSignature.end());
        detail::appendI32<ByteOrder::Little>(out, kPc2Version);
        detail::appendI32<ByteOrder::Little>(out, static_cast<std::int32_t>(info.pointCount));
        detail::appendF32<ByteOrder::Little>(out, static_cast<float>(info.startFrame));
        detail::appendF32<ByteOrder::Little>(out, 1.0f);  // one sample per frame (a frame step, see above)
        detail::appendI32<ByteOrder::Little>(out, static_cast<std::int32_t>(info.frameCount));
        return Status::success();
    }

    void encodeFrame(std::span<const Vec3f> positions, std::vector<std::uint8_t>& out) const override {
        detail::appendFrame<ByteOrder::Little>(out, positions);
    }
};

}  // namespace

namespace detail {

std::unique_ptr<VertexCacheWriter> makePc2Writer() { return std::make_unique<Pc2Writer>(); }

/// The "pc2" export (io/export/export_formats.cpp).
std::unique_ptr<ClipWriter> makePc2Export(const std::filesystem::path&, const ClipExportOptions&) {
    return makeVertexCacheClipWriter([](const Mesh&) { return makePc2Writer(); });
}

}  // namespace detail

Result<VertexCache> readPc2(const std::filesystem::path& path) {
    detail::InputFile file(path);
    if (Status s = file.open(); !s)
        return s;
    const std::string name = detail::quoted(path);
    std::array<std::uint8_t, kHeaderSize> header{};
    const std::size_t headerBytes =
        static_cast<std::size_t>(std::min<std::uint64_t>(file.size(), kHeaderSize));
    if (Status s = file.read(header.data(), headerBytes); !s)
        return s;
    if (headerBytes < kSignature.size() ||
        std::memcmp(header.data(), kSignature.data(), kSignature.size()) != 0)
        return Status::error(name +
                             " is not a PC2 file: it does not start with the signature \"POINTCACHE2\"");
    if (headerBytes < kHeaderSize)
        return Status::error(name + " is truncated: the PC2 header needs 32 bytes but the file has " +
                             std::to_string(file.size()));

    const std::int32_t version = detail::loadI32<ByteOrder::Little>(&header[12]);
    const std::int32_t points = detail::loadI32<ByteOrder::Little>(&header[16]);
    const float startFrame = detail::loadF32<ByteOrder::Little>(&header[20]);
    const std::int32_t samples = detail::loadI32<ByteOrder::Little>(&header[28]);
    if (version != kPc2Version)
        return Status::error(name + " has PC2 version " + std::to_string(version) +
                             "; only version 1 exists");
    if (points <= 0)
        return Status::error(name + " announces " + std::to_string(points) +
                             " points; a PC2 file needs at least 1");
    if (samples < 0)
        return Status::error(name + " announces a negative number of samples (" +
                             std::to_string(samples) + ")");
    const std::uint64_t frameBytes = static_cast<std::uint64_t>(points) * kPc2BytesPerPoint;
    const std::optional<std::uint64_t> expected =
        detail::checkedSize(kHeaderSize, static_cast<std::uint64_t>(samples), frameBytes);
    if (expected != file.size())
        return detail::sizeMismatch(
            path, std::to_string(samples) + " samples of " + std::to_string(points) + " points", expected,
            file.size());

    VertexCache cache;
    cache.info.pointCount = static_cast<std::size_t>(points);
    cache.info.frameCount = static_cast<std::size_t>(samples);
    cache.info.fps = 0.0;  // PC2 has no frame rate; sampleRate is a frame step (see the top of this file)
    cache.info.startFrame = startFrame;
    cache.frames.reserve(cache.info.frameCount);
    std::vector<std::uint8_t> buffer(static_cast<std::size_t>(samples > 0 ? frameBytes : 0));  // see readMdd
    for (std::int32_t i = 0; i < samples; ++i) {
        if (Status s = file.read(buffer.data(), buffer.size()); !s)
            return s;
        cache.frames.push_back(detail::loadFrame<ByteOrder::Little>(buffer.data(), cache.info.pointCount));
    }
    return cache;
}

}  // namespace softtouch::io
