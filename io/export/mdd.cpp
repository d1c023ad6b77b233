// MDD, the point cache of LightWave (Motion Designer), read by Blender's Mesh Cache modifier, 3ds Max
// and Cinema 4D. No signature, no version, no frame rate: each frame carries its time instead.
//
//   offset        size  field (big-endian)
//        0           4  int32    numFrames
//        4           4  int32    numPoints
//        8   4×frames   float32  time of each frame, in seconds
//        …           …  numFrames × numPoints × float32[3] (x, y, z)
//
// We write time i = (startFrame + i) / fps, so frame numbers survive a round trip through seconds.

#include "io/export/vertex_cache.h"

#include "io/export/clip_writer_internal.h"
#include "io/export/vertex_cache_internal.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softtouch::io {

namespace {

using detail::ByteOrder;

constexpr std::uint64_t kCountsSize = 8;
constexpr std::uint64_t kBytesPerTime = 4;
constexpr std::uint64_t kMddBytesPerPoint = 12;

class MddWriter final : public detail::SingleFileCacheWriter {
protected:
    Status encodeHeader(const std::filesystem::path& path, const CacheInfo& info,
                        std::vector<std::uint8_t>& out) const override {
        constexpr auto kMaxCount = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
        if (info.pointCount > kMaxCount || info.frameCount > kMaxCount)
            return Status::error("cannot write " + detail::quoted(path) + ": MDD stores at most " +
                                 std::to_string(kMaxCount) + " points and frames");
        // Times are monotonic in i, so the first and last bound them all. Checked rather than cast
        // blindly: a double beyond float's range has no float value.
        const double first = info.startFrame / info.fps;
        const double last = (info.startFrame + static_cast<double>(info.frameCount - 1)) / info.fps;
        constexpr double kFloatMax = std::numeric_limits<float>::max();
        if (!(std::abs(first) <= kFloatMax && std::abs(last) <= kFloatMax))
            return Status::error("cannot write " + detail::quoted(path) + ": frame times from " +
                                 detail::formatNumber(first) + " s do not fit MDD's float32");
        detail::appendI32<ByteOrder::Big>(out, static_cast<std::int32_t>(info.frameCount));
        detail::appendI32<ByteOrder::Big>(out, static_cast<std::int32_t>(info.pointCount));
        out.reserve(out.size() + info.frameCount * kBytesPerTime);
        for (std::size_t i = 0; i < info.frameCount; ++i) {
            // One division per time rather than start/fps + i/fps: one rounding instead of three.
            const double seconds = (info.startFrame + static_cast<double>(i)) / info.fps;
            detail::appendF32<ByteOrder::Big>(out, static_cast<float>(seconds));
        }
        return Status::success();
    }

    void encodeFrame(std::span<const Vec3f> positions, std::vector<std::uint8_t>& out) const override {
        detail::appendFrame<ByteOrder::Big>(out, positions);
    }
};

/// Frame rate and start frame recovered from MDD's times; fps = 0 means unknown.
struct TimeBase {
    double fps = 0.0;         ///< Frames per second; 0 when fewer than two increasing times.
    double startFrame = 0.0;  ///< Frame number of the first time; 0 when fps is unknown.
};

/// True when every time is exactly what MddWriter (and Blender's exporter, with start 0) writes for
/// this frame rate and start frame.
bool reproducesTimes(const std::vector<float>& times, double fps, double startFrame) {
    for (std::size_t i = 0; i < times.size(); ++i) {
        const double seconds = (startFrame + static_cast<double>(i)) / fps;
        // Beyond float's range there is no float to compare with (and the cast would be undefined).
        if (!(std::abs(seconds) <= std::numeric_limits<float>::max()) ||
            static_cast<float>(seconds) != times[i])
            return false;
    }
    return true;
}

TimeBase recoverTimeBase(const std::vector<float>& times) {
    if (times.size() < 2 || !(times.back() > times.front()))
        return {};
    // The average spacing rather than the first two times: float32 times far from zero carry ~1e-7
    // relative error each, which the whole span divides by frames - 1. For evenly spaced times (all
    // we write) both agree.
    const double first = times.front();
    const double estimate =
        static_cast<double>(times.size() - 1) / (static_cast<double>(times.back()) - first);
    if (!std::isfinite(estimate))
        return {};
    // The estimate is still off in the 5th or 6th digit (24 comes back as 23.99998), which start
    // frames in the thousands turn into whole hundredths of a frame. Rates and start frames people
    // use are round numbers — whole fps, NTSC's n·1000/1001, a few decimals — so when such a pair
    // reproduces every stored time bit for bit, it is what was written.
    const double rateCandidates[] = {std::round(estimate),
                                     std::round(estimate * 1001.0 / 1000.0) * 1000.0 / 1001.0,
                                     std::round(estimate * 1000.0) / 1000.0};
    for (double fps : rateCandidates) {
        if (!(fps > 0.0))
            continue;
        for (double startFrame : {std::round(first * fps), std::round(first * fps * 1000.0) / 1000.0}) {
            if (reproducesTimes(times, fps, startFrame))
                return {fps, startFrame};
        }
    }
    return {estimate, first * estimate};
}

}  // namespace

namespace detail {

std::unique_ptr<VertexCacheWriter> makeMddWriter() { return std::make_unique<MddWriter>(); }

/// The "mdd" export (io/export/export_formats.cpp).
std::unique_ptr<ClipWriter> makeMddExport(const std::filesystem::path&, const ClipExportOptions&) {
    return makeVertexCacheClipWriter([](const Mesh&) { return makeMddWriter(); });
}

}  // namespace detail

Result<VertexCache> readMdd(const std::filesystem::path& path) {
    detail::InputFile file(path);
    if (Status s = file.open(); !s)
        return s;
    const std::string name = detail::quoted(path);
    if (file.size() < kCountsSize)
        return Status::error(name + " is truncated: an MDD file starts with 8 bytes of counts but it has " +
                             std::to_string(file.size()));
    std::uint8_t counts[kCountsSize];
    if (Status s = file.read(counts, sizeof counts); !s)
        return s;
    const std::int32_t frames = detail::loadI32<ByteOrder::Big>(&counts[0]);
    const std::int32_t points = detail::loadI32<ByteOrder::Big>(&counts[4]);
    // MDD has no signature, so sane counts and an exact size are all that tell it from other data.
    if (frames < 0)
        return Status::error(name + " announces a negative number of frames (" + std::to_string(frames) +
                             "); is it an MDD file?");
    if (points <= 0)
        return Status::error(name + " announces " + std::to_string(points) +
                             " points; an MDD file needs at least 1 (is it an MDD file?)");
    const std::uint64_t frameBytes = static_cast<std::uint64_t>(points) * kMddBytesPerPoint;
    const std::optional<std::uint64_t> expected =
        detail::checkedSize(kCountsSize, static_cast<std::uint64_t>(frames), kBytesPerTime + frameBytes);
    if (expected != file.size())
        return detail::sizeMismatch(
            path, std::to_string(frames) + " frames of " + std::to_string(points) + " points", expected,
            file.size());

    VertexCache cache;
    cache.info.pointCount = static_cast<std::size_t>(points);
    cache.info.frameCount = static_cast<std::size_t>(frames);
    // A frame's buffer only when there are frames: a header of 0 frames and 671 million points has the
    // exact size of an empty file (fuzz_cache found it asking for 8 GB).
    std::vector<std::uint8_t> buffer(static_cast<std::size_t>(frames > 0 ? std::max<std::uint64_t>(frameBytes, 8) : 8));
    std::vector<float> times(static_cast<std::size_t>(frames));
    for (float& seconds : times) {
        if (Status s = file.read(buffer.data(), kBytesPerTime); !s)
            return s;
        seconds = detail::loadF32<ByteOrder::Big>(buffer.data());
    }
    const TimeBase timeBase = recoverTimeBase(times);
    cache.info.fps = timeBase.fps;
    cache.info.startFrame = timeBase.startFrame;
    cache.frames.reserve(cache.info.frameCount);
    for (std::int32_t i = 0; i < frames; ++i) {
        if (Status s = file.read(buffer.data(), static_cast<std::size_t>(frameBytes)); !s)
            return s;
        cache.frames.push_back(detail::loadFrame<ByteOrder::Big>(buffer.data(), cache.info.pointCount));
    }
    return cache;
}

}  // namespace softtouch::io
