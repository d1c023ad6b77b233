#include "io/export/vertex_cache.h"

#include "io/export/vertex_cache_internal.h"
#include "io/files/atomic_file.h"

#include <charconv>
#include <string>

namespace softtouch::io {

namespace {

// Text is handed to the file in pieces of about this size: a large mesh never sits in memory twice.
constexpr std::size_t kChunkBytes = 1 << 20;

void appendFloat(std::string& out, float value) {
    // std::to_chars without a precision writes the shortest text that reads back to the same float:
    // the exact round trip "%.9g" promises, without its noise digits ("0.1" rather than
    // "0.100000001") and without printf's locale (a Qt application calls setlocale(), and a German
    // locale would turn "0.5" into "0,5").
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, result.ptr);
}

void appendIndex(std::string& out, std::uint64_t index) {
    char buffer[24];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, index);
    out.append(buffer, result.ptr);
}

Status flushChunk(AtomicFile& file, std::string& text, bool force) {
    if (text.empty() || (!force && text.size() < kChunkBytes))
        return Status::success();
    Status s = file.write(text.data(), text.size());
    text.clear();
    return s;
}

}  // namespace

namespace detail {

void appendObjVector(std::string& out, const char* tag, const Vec3f& v) {
    out += tag;
    for (int axis = 0; axis < 3; ++axis) {
        out += ' ';
        appendFloat(out, v[axis]);
    }
    out += '\n';
}

void appendObjFace(std::string& out, const std::array<std::uint32_t, 3>& triangle, bool withNormals) {
    out += 'f';
    for (std::uint32_t index : triangle) {
        const std::uint64_t oneBased = std::uint64_t(index) + 1;  // OBJ counts from 1
        out += ' ';
        appendIndex(out, oneBased);
        if (withNormals) {
            out += "//";
            appendIndex(out, oneBased);
        }
    }
    out += '\n';
}

void appendObjGroup(std::string& text, const std::vector<MeshPart>& parts, const std::array<std::uint32_t, 3>& triangle,
                    int& current) {
    int part = current;
    for (std::size_t p = 0; p < parts.size(); ++p)
        if (triangle[0] >= parts[p].firstVertex && triangle[0] < parts[p].firstVertex + parts[p].vertexCount)
            part = int(p);
    if (part == current || part < 0)
        return;
    current = part;
    std::string name = parts[std::size_t(part)].name.empty() ? "part_" + std::to_string(part) : parts[std::size_t(part)].name;
    for (char& c : name)  // one token: OBJ splits group names at white space
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r')
            c = '_';
    text += "g " + name + "\n";
}

}  // namespace detail

Status writeObj(const std::filesystem::path& path, const Mesh& mesh, std::span<const Vec3f> positions,
                std::span<const Vec3f> normals, bool groups) {
    const std::span<const Vec3f> points =
        positions.empty() ? std::span<const Vec3f>(mesh.positions) : positions;
    const std::span<const Vec3f> vertexNormals =
        normals.empty() ? std::span<const Vec3f>(mesh.normals) : normals;
    const std::string nothingWritten = "; nothing was written to " + detail::quoted(path);
    if (points.empty())
        return Status::error("the mesh has no vertices" + nothingWritten);
    if (!vertexNormals.empty() && vertexNormals.size() != points.size())
        return Status::error("the mesh has " + std::to_string(vertexNormals.size()) + " normals for " +
                             std::to_string(points.size()) + " vertices" + nothingWritten);
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!isFinite(points[i]))
            return Status::error("vertex " + std::to_string(i) + " is not finite" + nothingWritten);
    }
    for (std::size_t i = 0; i < vertexNormals.size(); ++i) {
        if (!isFinite(vertexNormals[i]))
            return Status::error("normal " + std::to_string(i) + " is not finite" + nothingWritten);
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (std::uint32_t index : mesh.triangles[t]) {
            if (index >= points.size())
                return Status::error("triangle " + std::to_string(t) + " uses vertex " +
                                     std::to_string(index) + " of " + std::to_string(points.size()) +
                                     nothingWritten);
        }
    }

    AtomicFile file(path);
    if (Status s = file.open(); !s)
        return s;
    // No "o"/"g" lines unless asked: importers split objects and groups into separate meshes (and may
    // reorder or weld vertices while doing so), which would break the 1:1 vertex mapping onto the caches.
    std::string text = "# SoftTouch rest mesh: vertex order matches the vertex caches written beside it\n";
    for (const Vec3f& p : points) {
        detail::appendObjVector(text, "v", p);
        if (Status s = flushChunk(file, text, false); !s)
            return s;
    }
    for (const Vec3f& n : vertexNormals) {
        detail::appendObjVector(text, "vn", n);
        if (Status s = flushChunk(file, text, false); !s)
            return s;
    }
    int part = -1;
    for (const auto& triangle : mesh.triangles) {
        if (groups)
            detail::appendObjGroup(text, mesh.parts, triangle, part);
        detail::appendObjFace(text, triangle, !vertexNormals.empty());
        if (Status s = flushChunk(file, text, false); !s)
            return s;
    }
    if (Status s = flushChunk(file, text, true); !s)
        return s;
    return file.commit();
}

}  // namespace softtouch::io
