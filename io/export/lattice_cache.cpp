// Lattice cache: <base>.lattice.glb (the rest mesh with each vertex's lattice parameters) and
// <base>.lattice.bin (node positions per frame). docs/formats.md, "Lattice cache", is the reference.
//
// .lattice.bin:
//   offset  size  field
//        0     8  "STLATC\r\n"               signature (the \r\n catches text-mode transfers)
//        8     4  uint32 LE  headerBytes     length of the JSON header, a multiple of 4
//       12     …  UTF-8 JSON header, padded with spaces to headerBytes
//   12 + headerBytes …  frameCount frames; a frame is every object's nodes in object order, a node
//                      3 float32 LE (x, y, z metres); within an object index = i + nx*(j + ny*k)
//
// The mesh (GLB, one primitive per object, indices local to the primitive):
//   POSITION, NORMAL  rest pose;   _LATTICE_UVW (VEC3 float) the vertex's (u,v,w);
//   TEXCOORD_0 = (u, v), TEXCOORD_1 = (w, object index)   for engines that import only UV sets.
//
// Streaming: the .bin is written through AtomicFile a frame at a time (one frame of nodes in
// memory); the GLB is built in finish() from the rest mesh.

#include "io/export/lattice_cache.h"

#include "io/export/clip_writer_internal.h"
#include "io/export/vertex_cache_internal.h"
#include "io/files/atomic_file.h"
#include "io/files/json_reader.h"

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

namespace softtouch::io {

namespace detail {

/// The files of a lattice cache at the base path `path`: the mesh with its lattice coordinates, then the
/// node positions per frame.
std::vector<std::filesystem::path> latticeFiles(const std::filesystem::path& path, std::size_t) {
    return {std::filesystem::path(path) += ".lattice.glb", std::filesystem::path(path) += ".lattice.bin"};
}

}  // namespace detail

namespace {

using detail::ByteOrder;

constexpr std::uint64_t kPrefixBytes = 12;  // signature + header length

/// The clamped uniform knot vector AxisBasis uses: degree+1 zeros, uniform interior knots,
/// degree+1 ones.
std::vector<double> clampedKnots(int count, int degree) {
    const int spans = count - degree;
    std::vector<double> knots(std::size_t(degree), 0.0);
    for (int s = 0; s <= spans; ++s)
        knots.push_back(double(s) / double(spans));
    knots.insert(knots.end(), std::size_t(degree), 1.0);
    return knots;
}

nlohmann::json vectorJson(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

class LatticeCacheWriter final : public ClipWriter {
public:
    Status begin(const std::filesystem::path& path, const ClipSetup& setup) override {
        abort();
        m_warnings.clear();
        const std::vector<std::filesystem::path> outputs = detail::latticeFiles(path, setup.info.frameCount);
        if (Status s = detail::checkCacheInfo(outputs[1], setup.info); !s)
            return s;
        if (setup.objects.empty())
            return Status::error("cannot write " + detail::quoted(outputs[1]) + ": the clip has no objects");
        if (setup.restMesh.normals.size() != setup.restMesh.positions.size())
            return Status::error("cannot write " + detail::quoted(outputs[0]) + ": the rest mesh needs one normal per vertex");
        if (Status s = detail::checkWritable(outputs[0]); !s)
            return s;
        m_path = path;
        m_setup = setup;
        m_bin.emplace(outputs[1]);
        m_mesh = std::make_unique<detail::StagedFile>(outputs[0]);
        std::string header = headerJson(outputs[0].filename().string()).dump();
        header.append((4 - header.size() % 4) % 4, ' ');  // node data starts 4-aligned
        std::vector<std::uint8_t> prefix(std::begin(kLatticeCacheSignature), std::end(kLatticeCacheSignature));
        prefix.resize(kPrefixBytes);
        detail::storeU32<ByteOrder::Little>(prefix.data() + 8, std::uint32_t(header.size()));
        prefix.insert(prefix.end(), header.begin(), header.end());
        Status s = m_bin->open();
        if (s)
            s = m_bin->write(prefix.data(), prefix.size());
        if (!s) {
            abort();
            return s;
        }
        m_framesWritten = 0;
        return Status::success();
    }

    Status writeFrame(const FrameData& frame) override {
        if (!m_bin)
            return Status::error("no lattice cache is being written: begin() was not called or the write failed");
        if (Status s = checkFrameData(m_path, m_framesWritten, m_setup, frame, false, true); !s) {
            abort();
            return s;
        }
        m_buffer.clear();
        for (std::size_t o = 0; o < frame.nodes.size(); ++o) {
            for (std::size_t n = 0; n < frame.nodes[o].size(); ++n) {
                const Vec3& p = frame.nodes[o][n];
                if (p.cwiseAbs().maxCoeff() > double(std::numeric_limits<float>::max())) {
                    Status s = Status::error("frame " + std::to_string(m_framesWritten) + " object " + std::to_string(o) +
                                             " lattice node " + std::to_string(n) +
                                             " does not fit float32; nothing was written to " + detail::quoted(m_path));
                    abort();
                    return s;
                }
                detail::appendF32<ByteOrder::Little>(m_buffer, float(p.x()));
                detail::appendF32<ByteOrder::Little>(m_buffer, float(p.y()));
                detail::appendF32<ByteOrder::Little>(m_buffer, float(p.z()));
            }
        }
        if (Status s = m_bin->write(m_buffer.data(), m_buffer.size()); !s) {
            abort();
            return s;
        }
        ++m_framesWritten;
        return Status::success();
    }

    Status finish() override {
        if (!m_bin)
            return Status::error("no lattice cache is being written: begin() was not called or the write failed");
        if (m_framesWritten != m_setup.info.frameCount) {
            Status s = detail::frameCountMismatch(m_path, m_framesWritten, m_setup.info.frameCount);
            abort();
            return s;
        }
        Result<std::string> mesh = meshBytes();
        Status s = mesh ? m_mesh->write(mesh.value()) : Status::error(mesh.message());
        // The mesh first, the node file last: a .bin is never published without its mesh.
        if (s)
            s = m_mesh->publish();
        if (s)
            s = m_bin->commit();
        abort();
        return s;
    }

    void abort() override {
        m_bin.reset();   // AtomicFile's destructor removes its temporary
        m_mesh.reset();  // so does StagedFile's, unless published
        m_framesWritten = 0;
        m_buffer.clear();
    }

    bool needsNodes() const override { return true; }

private:
    nlohmann::json headerJson(const std::string& meshName) const {
        nlohmann::json objects = nlohmann::json::array();
        std::size_t firstNode = 0;
        for (std::size_t o = 0; o < m_setup.objects.size(); ++o) {
            const ClipObject& object = m_setup.objects[o];
            const Lattice& lattice = object.lattice;
            nlohmann::json j;
            j["name"] = object.name;
            j["primitive"] = o;
            j["firstVertex"] = object.firstVertex;
            j["vertexCount"] = object.vertexCount;
            j["firstNode"] = firstNode;
            j["kind"] = lattice.shape().kind == LatticeKind::Bezier ? "bezier" : "bspline";
            j["nodes"] = {lattice.count(0), lattice.count(1), lattice.count(2)};
            j["degrees"] = {lattice.axis(0).degree(), lattice.axis(1).degree(), lattice.axis(2).degree()};
            nlohmann::json knots = nlohmann::json::array();
            for (int a = 0; a < 3; ++a)
                knots.push_back(clampedKnots(lattice.count(a), lattice.axis(a).degree()));
            j["knots"] = knots;
            const OrientedBox& box = lattice.box();
            j["box"] = {{"origin", vectorJson(box.origin)},
                        {"axes", {vectorJson(box.axes.col(0)), vectorJson(box.axes.col(1)), vectorJson(box.axes.col(2))}},
                        {"size", vectorJson(box.size)}};
            objects.push_back(j);
            firstNode += std::size_t(lattice.nodeCount());
        }
        nlohmann::json header;
        header["format"] = "softtouch-lattice-cache";
        header["version"] = 1;
        header["fps"] = m_setup.info.fps;
        header["frameCount"] = m_setup.info.frameCount;
        header["startFrame"] = m_setup.info.startFrame;
        header["mesh"] = meshName;
        header["nodesPerFrame"] = firstNode;
        header["node"] = "float32 x, y, z, little-endian, metres";
        header["nodeOrder"] = "index = i + nx*(j + ny*k), objects in order";
        header["objects"] = objects;
        return header;
    }

    Result<std::string> meshBytes() const {
        const Mesh& rest = m_setup.restMesh;
        tinygltf::Model model;
        model.asset.version = "2.0";
        model.asset.generator = "SoftTouch (lattice cache)";
        model.buffers.emplace_back();
        tinygltf::Mesh mesh;
        mesh.name = "lattice";
        std::vector<float> uvw;
        std::vector<float> uv;
        std::vector<float> w;
        for (std::size_t o = 0; o < m_setup.objects.size(); ++o) {
            const ClipObject& object = m_setup.objects[o];
            const std::size_t n = object.vertexCount;
            uvw.resize(3 * n);
            uv.resize(2 * n);
            w.resize(2 * n);
            for (std::size_t v = 0; v < n; ++v) {
                const Vec3 p = object.lattice.box().toParameters(rest.positions[object.firstVertex + v].cast<double>());
                for (int c = 0; c < 3; ++c)
                    uvw[3 * v + std::size_t(c)] = float(p[c]);
                uv[2 * v] = float(p.x());
                uv[2 * v + 1] = float(p.y());
                w[2 * v] = float(p.z());
                w[2 * v + 1] = float(o);
            }
            tinygltf::Primitive primitive;
            primitive.mode = TINYGLTF_MODE_TRIANGLES;
            primitive.attributes["POSITION"] =
                detail::addFloatAccessor(model, rest.positions[object.firstVertex].data(), n, 3, true, true);
            primitive.attributes["NORMAL"] =
                detail::addFloatAccessor(model, rest.normals[object.firstVertex].data(), n, 3, true, false);
            primitive.attributes["_LATTICE_UVW"] = detail::addFloatAccessor(model, uvw.data(), n, 3, true, false);
            primitive.attributes["TEXCOORD_0"] = detail::addFloatAccessor(model, uv.data(), n, 2, true, false);
            primitive.attributes["TEXCOORD_1"] = detail::addFloatAccessor(model, w.data(), n, 2, true, false);
            primitive.indices = detail::addIndexAccessor(
                model, std::span(rest.triangles).subspan(object.firstTriangle, object.triangleCount), object.firstVertex);
            mesh.primitives.push_back(primitive);
        }
        model.meshes.push_back(mesh);
        tinygltf::Node node;
        node.mesh = 0;
        model.nodes.push_back(node);
        tinygltf::Scene scene;
        scene.nodes.push_back(0);
        model.scenes.push_back(scene);
        model.defaultScene = 0;
        return detail::serializeGltf(model, true, m_mesh->target());
    }

    std::filesystem::path m_path;
    ClipSetup m_setup;                             ///< Copied by begin().
    std::optional<AtomicFile> m_bin;               ///< The node file, open between begin() and finish().
    std::unique_ptr<detail::StagedFile> m_mesh;    ///< The GLB, staged in finish().
    std::vector<std::uint8_t> m_buffer;            ///< One frame's node bytes, reused.
    std::size_t m_framesWritten = 0;
};

}  // namespace

namespace detail {

/// The "lattice" export (io/export/export_formats.cpp).
std::unique_ptr<ClipWriter> makeLatticeExport(const std::filesystem::path&, const ClipExportOptions&) {
    return std::make_unique<LatticeCacheWriter>();
}

}  // namespace detail

Result<LatticeCache> readLatticeCache(const std::filesystem::path& path) {
    detail::InputFile file(path);
    if (Status s = file.open(); !s)
        return s;
    const std::string name = detail::quoted(path);
    std::uint8_t prefix[kPrefixBytes] = {};
    if (file.size() < kPrefixBytes || !file.read(prefix, kPrefixBytes) ||
        std::memcmp(prefix, kLatticeCacheSignature, sizeof kLatticeCacheSignature) != 0)
        return Status::error(name + " is not a lattice cache: it does not start with \"STLATC\\r\\n\"");
    const std::uint32_t headerBytes = detail::loadU32<ByteOrder::Little>(prefix + 8);
    if (file.size() < kPrefixBytes + headerBytes)
        return Status::error(name + " is truncated: its JSON header needs " + std::to_string(headerBytes) +
                             " bytes after byte 12, the file has " + std::to_string(file.size()) + " bytes");
    std::string text(headerBytes, '\0');
    if (Status s = file.read(text.data(), text.size()); !s)
        return s;
    const nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
    if (json.is_discarded())
        return Status::error(name + ": the header (bytes 12 to " + std::to_string(12 + headerBytes) +
                             ") is not valid JSON");

    JsonIssues issues(path.string());
    const JsonValue root(&json, "", &issues);
    LatticeCache cache;
    cache.nodeDataOffset = kPrefixBytes + headerBytes;
    if (root["format"].string(true).value_or("") != "softtouch-lattice-cache")
        root["format"].problem("expected \"softtouch-lattice-cache\"");
    root["version"].integer(1, 1, true);
    cache.fps = root["fps"].number(1e-9, 1e6, "fps", true).value_or(0.0);
    cache.frameCount = std::size_t(root["frameCount"].integer(0, std::numeric_limits<int>::max(), true).value_or(0));
    cache.mesh = root["mesh"].string(true).value_or("");
    const JsonValue objects = root["objects"];
    if (!objects.isArray() || objects.size() == 0)
        objects.problem("expected a non-empty array of objects");
    std::size_t nodesPerFrame = 0;
    for (std::size_t o = 0; o < objects.size(); ++o) {
        const JsonValue j = objects.at(o);
        LatticeCacheObject object;
        object.name = j["name"].string().value_or("");
        object.firstVertex = std::uint32_t(j["firstVertex"].integer(0, std::numeric_limits<int>::max(), true).value_or(0));
        object.vertexCount = std::uint32_t(j["vertexCount"].integer(1, std::numeric_limits<int>::max(), true).value_or(0));
        const std::string kind = j["kind"].string(true).value_or("");
        if (kind != "bezier" && kind != "bspline")
            j["kind"].problem("expected \"bezier\" or \"bspline\", got \"" + kind + "\"");
        object.kind = kind == "bspline" ? LatticeKind::BSpline : LatticeKind::Bezier;
        object.nodes = j["nodes"].int3(2, 64, true).value_or(std::array<int, 3>{2, 2, 2});
        object.degrees = j["degrees"].int3(1, kMaxBasisOrder - 1, true).value_or(std::array<int, 3>{1, 1, 1});
        for (int a = 0; a < 3; ++a) {
            const auto axis = std::size_t(a);
            const JsonValue knots = j["knots"].at(axis);
            const std::size_t expected = std::size_t(object.nodes[axis] + object.degrees[axis] + 1);
            if (object.degrees[axis] >= object.nodes[axis])
                j["degrees"].at(axis).problem("the degree must be below the node count " + std::to_string(object.nodes[axis]));
            if (knots.size() != expected) {
                knots.problem("expected " + std::to_string(expected) + " knots (nodes + degree + 1)");
                continue;
            }
            for (std::size_t k = 0; k < expected; ++k)
                object.knots[axis].push_back(knots.at(k).number(0.0, 1.0, "", true).value_or(0.0));
        }
        const JsonValue box = j["box"];
        object.box.origin = box["origin"].vec3(true).value_or(Vec3::Zero());
        for (int a = 0; a < 3; ++a)
            object.box.axes.col(a) = box["axes"].at(std::size_t(a)).vec3(true).value_or(Vec3::Unit(a));
        object.box.size = box["size"].vec3(true).value_or(Vec3::Ones());
        if (Status s = object.box.validate(); !s)
            box.problem(s.message());
        nodesPerFrame += std::size_t(object.nodeCount());
        cache.objects.push_back(std::move(object));
    }
    if (!issues.empty())
        return Status::error(issues.summary());

    const std::optional<std::uint64_t> expected =
        detail::checkedSize(kPrefixBytes + headerBytes, cache.frameCount, nodesPerFrame * 12);
    if (expected != file.size())
        return detail::sizeMismatch(path, std::to_string(cache.frameCount) + " frames of " +
                                              std::to_string(nodesPerFrame) + " nodes",
                                    expected, file.size());
    std::vector<std::uint8_t> buffer(nodesPerFrame * 12);
    cache.frames.reserve(cache.frameCount);
    for (std::size_t f = 0; f < cache.frameCount; ++f) {
        if (Status s = file.read(buffer.data(), buffer.size()); !s)
            return s;
        cache.frames.push_back(detail::loadFrame<ByteOrder::Little>(buffer.data(), nodesPerFrame));
    }
    return cache;
}

}  // namespace softtouch::io
