#pragma once
/// Internals shared by the vertex-cache writers and readers (atomic_file.cpp, vertex_cache.cpp,
/// pc2.cpp, mdd.cpp, obj_sequence.cpp, obj_writer.cpp). Not part of the io API: include it from
/// io/*.cpp only.

#include "io/export/vertex_cache.h"
#include "io/files/atomic_file.h"
#include "io/files/file_text.h"

#include <array>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace softtouch::io::detail {

// ---- Byte order ---------------------------------------------------------------------------------
// Cache formats fix their byte order (PC2 little-endian, MDD big-endian) whatever the host's, so
// values are serialised byte by byte rather than by copying host structs.

/// Byte order of a file format.
enum class ByteOrder { Little, Big };

/// Stores `value` into out[0..3] in the given byte order.
template <ByteOrder order>
inline void storeU32(std::uint8_t* out, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) {
        const int shift = order == ByteOrder::Little ? 8 * i : 8 * (3 - i);
        out[i] = static_cast<std::uint8_t>(value >> shift);
    }
}

/// Reads in[0..3] in the given byte order.
template <ByteOrder order>
inline std::uint32_t loadU32(const std::uint8_t* in) {
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i) {
        const int shift = order == ByteOrder::Little ? 8 * i : 8 * (3 - i);
        value |= static_cast<std::uint32_t>(in[i]) << shift;
    }
    return value;
}

/// Appends a two's-complement int32.
template <ByteOrder order>
inline void appendI32(std::vector<std::uint8_t>& out, std::int32_t value) {
    out.resize(out.size() + 4);
    storeU32<order>(out.data() + out.size() - 4, static_cast<std::uint32_t>(value));
}

/// Appends an IEEE-754 binary32.
template <ByteOrder order>
inline void appendF32(std::vector<std::uint8_t>& out, float value) {
    out.resize(out.size() + 4);
    storeU32<order>(out.data() + out.size() - 4, std::bit_cast<std::uint32_t>(value));
}

/// Reads a two's-complement int32.
template <ByteOrder order>
inline std::int32_t loadI32(const std::uint8_t* in) {
    return static_cast<std::int32_t>(loadU32<order>(in));
}

/// Reads an IEEE-754 binary32.
template <ByteOrder order>
inline float loadF32(const std::uint8_t* in) {
    return std::bit_cast<float>(loadU32<order>(in));
}

/// Appends one frame as numPoints x,y,z float32 triplets, the frame layout PC2 and MDD share.
template <ByteOrder order>
inline void appendFrame(std::vector<std::uint8_t>& out, std::span<const Vec3f> positions) {
    out.reserve(out.size() + positions.size() * 12);
    for (const Vec3f& p : positions) {
        appendF32<order>(out, p.x());
        appendF32<order>(out, p.y());
        appendF32<order>(out, p.z());
    }
}

/// Decodes one frame written by appendFrame().
template <ByteOrder order>
inline std::vector<Vec3f> loadFrame(const std::uint8_t* in, std::size_t pointCount) {
    std::vector<Vec3f> frame(pointCount);
    for (std::size_t i = 0; i < pointCount; ++i, in += 12)
        frame[i] = Vec3f(loadF32<order>(in), loadF32<order>(in + 4), loadF32<order>(in + 8));
    return frame;
}

// ---- Checks every writer shares -----------------------------------------------------------------

/// Checks what begin() is given: at least one point and one frame, finite fps > 0, finite start.
Status checkCacheInfo(const std::filesystem::path& path, const CacheInfo& info);

/// Checks frame number `frameIndex` (0-based) before it is written: announced, the right number of
/// vertices, all finite. Messages end in "nothing was written to '<path>'" because the caller aborts.
Status checkFrame(const std::filesystem::path& path, std::size_t frameIndex, const CacheInfo& info,
                  std::span<const Vec3f> positions);

/// The message of a finish() reached with `written` of `announced` frames.
Status frameCountMismatch(const std::filesystem::path& path, std::size_t written, std::size_t announced);

// ---- Single-file binary caches (PC2, MDD) --------------------------------------------------------

/// A cache written as one binary file: a header at begin(), one encoded frame per writeFrame(),
/// published by AtomicFile::commit() in finish(). Subclasses only encode.
class SingleFileCacheWriter : public VertexCacheWriter {
public:
    Status begin(const std::filesystem::path& path, const CacheInfo& info) final;
    Status writeFrame(std::span<const Vec3f> positions) final;
    Status finish() final;
    void abort() final;

protected:
    /// Checks the format's own limits (int32 counts, float32 times) and appends the header bytes.
    virtual Status encodeHeader(const std::filesystem::path& path, const CacheInfo& info,
                                std::vector<std::uint8_t>& out) const = 0;
    /// Appends one frame's bytes; the frame was already checked.
    virtual void encodeFrame(std::span<const Vec3f> positions, std::vector<std::uint8_t>& out) const = 0;

private:
    std::optional<AtomicFile> m_file;     ///< Open between begin() and finish()/abort().
    std::filesystem::path m_path;         ///< Target of the cache being written.
    CacheInfo m_info;                     ///< What begin() announced.
    std::size_t m_framesWritten = 0;      ///< Frames appended since begin().
    std::vector<std::uint8_t> m_buffer;   ///< One frame's bytes, reused: one frame in memory at a time.
};

/// The PC2 writer (pc2.cpp).
std::unique_ptr<VertexCacheWriter> makePc2Writer();
/// The MDD writer (mdd.cpp).
std::unique_ptr<VertexCacheWriter> makeMddWriter();
/// The OBJ-sequence writer; keeps a copy of the rest mesh's triangles (obj_sequence.cpp).
std::unique_ptr<VertexCacheWriter> makeObjSequenceWriter(const Mesh& restMesh);

// ---- Reading ------------------------------------------------------------------------------------

/// A file opened for reading, closed on destruction; errors name the file.
class InputFile {
public:
    /// Opens `path` (binary).
    explicit InputFile(std::filesystem::path path);
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;

    /// Opens the file and learns its size; "cannot read '<path>': <reason>" on failure.
    Status open();
    /// Size in bytes, known after open().
    std::uint64_t size() const { return m_size; }
    /// Reads exactly `size` bytes; the caller checked the file size first, so a short read is an I/O
    /// error or a file that changed while being read.
    Status read(void* data, std::size_t size);

private:
    std::filesystem::path m_path;
    std::FILE* m_file = nullptr;
    std::uint64_t m_size = 0;
};

/// The message for a file whose size is not what its header says: "is truncated" or "has N extra
/// bytes". `layout` describes what the header announced ("3 samples of 10 points"); `expected` is
/// nullopt when that size does not even fit 64 bits (garbage counts).
Status sizeMismatch(const std::filesystem::path& path, const std::string& layout,
                    std::optional<std::uint64_t> expected, std::uint64_t actual);

/// header + count * bytesEach, or nullopt when that overflows 64 bits (no real file is that big).
std::optional<std::uint64_t> checkedSize(std::uint64_t header, std::uint64_t count, std::uint64_t bytesEach);

// ---- OBJ text -----------------------------------------------------------------------------------

/// Appends "<tag> x y z\n" with each float in the shortest form that reads back to the same float
/// (locale-independent, unlike printf under a Qt application's setlocale()).
void appendObjVector(std::string& out, const char* tag, const Vec3f& v);

/// Appends "f a b c\n" (1-based), or "f a//a b//b c//c\n" when vertex normals are written.
void appendObjFace(std::string& out, const std::array<std::uint32_t, 3>& triangle, bool withNormals);

}  // namespace softtouch::io::detail
