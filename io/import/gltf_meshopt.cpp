// GLB compression (EXT_meshopt_compression, octahedral normals) and its reverse. The spec this follows:
// KhronosGroup/glTF, extensions/2.0/Vendor/EXT_meshopt_compression. Works on the GLB container (JSON chunk +
// binary chunk) rather than on a tinygltf model, because tinygltf reads neither a buffer without a URI (the
// extension's fallback buffer) nor the extension itself.

#include "io/import/gltf_meshopt.h"

#include "io/files/input_file.h"
#include "io/files/json_reader.h"

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <vector>

namespace softtouch::io {

namespace {

using nlohmann::json;

constexpr char kMeshopt[] = "EXT_meshopt_compression";
constexpr char kQuantization[] = "KHR_mesh_quantization";
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kBinChunk = 0x004E4942;   // "BIN\0"
/// Largest binary chunk expandGlb() builds: a corrupt view count must not ask for terabytes.
constexpr std::size_t kMaxExpandedBytes = std::size_t(1) << 31;
/// Most a view decodes to per compressed byte, with room to spare: the attribute codec spends at least two bits
/// on every 16 bytes, the index codec at least four bits on a triangle.
constexpr std::size_t kMaxExpansion = 128;
/// Bits per octahedral component for normals: 16 (stride 8) keeps them within 1e-4 rad.
constexpr int kOctahedralBits = 16;
/// Mantissa bits of morph-target deltas (the EXPONENTIAL filter, an exponent for every value: each within 2^-15
/// of itself). meshoptimizer 0.18 can share one exponent across a vector, but takes an exact 0 for exponent 0
/// then, which rounds the vector's other values to 2^-15 whatever their size.
constexpr int kExponentBits = 16;

constexpr int kFloat = 5126, kShort = 5122, kByte = 5120, kUnsignedShort = 5123, kUnsignedInt = 5125;

struct Glb {
    json document;
    std::string bin;
};

std::uint32_t readU32(const char* p) {
    return std::uint32_t(std::uint8_t(p[0])) | std::uint32_t(std::uint8_t(p[1])) << 8 | std::uint32_t(std::uint8_t(p[2])) << 16 |
           std::uint32_t(std::uint8_t(p[3])) << 24;
}

void appendU32(std::string& out, std::uint32_t v) {
    for (int b = 0; b < 4; ++b)
        out += char((v >> (8 * b)) & 0xFF);
}

void padTo4(std::string& s, char fill) {
    while (s.size() % 4 != 0)
        s += fill;
}

Result<Glb> parseGlb(std::string_view bytes, const std::string& name) {
    if (bytes.size() < 20 || bytes.substr(0, 4) != "glTF")
        return Status::error(name + " is not a GLB file (no 'glTF' header)");
    if (readU32(bytes.data() + 4) != 2)
        return Status::error(name + ": GLB version " + std::to_string(readU32(bytes.data() + 4)) + ", expected 2");
    const std::size_t length = readU32(bytes.data() + 8);
    if (length > bytes.size())
        return Status::error(name + " is truncated: its header states " + std::to_string(length) + " bytes, the file has " +
                             std::to_string(bytes.size()));
    const std::size_t jsonLength = readU32(bytes.data() + 12);
    if (readU32(bytes.data() + 16) != kJsonChunk || jsonLength > length - 20)
        return Status::error(name + ": the GLB's first chunk is not a JSON chunk that fits in the file");
    JsonIssues issues(name);
    auto document = parseJsonText(bytes.substr(20, jsonLength), issues);
    if (!document || !document->is_object())
        return Status::error(issues.empty() ? name + ": the GLB's JSON is not an object" : issues.summary());
    Glb glb{std::move(*document), {}};
    std::size_t at = 20 + jsonLength;
    if (length >= at + 8) {
        const std::size_t binLength = readU32(bytes.data() + at);
        if (readU32(bytes.data() + at + 4) != kBinChunk || binLength > length - at - 8)
            return Status::error(name + ": the GLB's second chunk is not a binary chunk that fits in the file");
        glb.bin.assign(bytes.data() + at + 8, binLength);
    }
    return glb;
}

std::string writeGlb(const json& document, std::string bin) {
    std::string text = document.dump();
    padTo4(text, ' ');
    padTo4(bin, '\0');
    std::string out;
    const std::size_t total = 12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size());
    out.reserve(total);
    out += "glTF";
    appendU32(out, 2);
    appendU32(out, std::uint32_t(total));
    appendU32(out, std::uint32_t(text.size()));
    appendU32(out, kJsonChunk);
    out += text;
    if (!bin.empty()) {
        appendU32(out, std::uint32_t(bin.size()));
        appendU32(out, kBinChunk);
        out += bin;
    }
    return out;
}

/// A non-negative integer member, or nothing when absent or of another type.
std::optional<std::size_t> natural(const json& object, const char* key) {
    if (!object.is_object())
        return std::nullopt;
    const auto it = object.find(key);
    if (it == object.end() || !it->is_number_integer() || it->get<std::int64_t>() < 0)
        return std::nullopt;
    return std::size_t(it->get<std::int64_t>());
}

std::size_t componentBytes(std::size_t type) {
    switch (type) {
    case 5120: case 5121: return 1;
    case 5122: case 5123: return 2;
    case 5125: case 5126: return 4;
    default: return 0;
    }
}

std::size_t componentCount(const json& accessor) {
    const auto it = accessor.find("type");
    if (it == accessor.end() || !it->is_string())
        return 0;
    const std::string type = it->get<std::string>();
    return type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : type == "MAT4" ? 16 : 0;
}

/// An accessor's element size in bytes (0 when it is not one this code lays out: matrices of small
/// components carry column padding).
std::size_t elementBytes(const json& accessor) {
    return componentBytes(natural(accessor, "componentType").value_or(0)) * componentCount(accessor);
}

void addExtension(json& document, const char* list, const char* name) {
    json& names = document[list];
    if (!names.is_array())
        names = json::array();
    if (std::find(names.begin(), names.end(), name) == names.end())
        names.push_back(name);
}

void removeExtension(json& document, const char* list, const char* name) {
    const auto it = document.find(list);
    if (it == document.end() || !it->is_array())
        return;
    it->erase(std::remove(it->begin(), it->end(), json(name)), it->end());
    if (it->empty())
        document.erase(list);
}

/// Whether a glTF document lists EXT_meshopt_compression among the extensions it uses.
bool listsMeshopt(const json& document) {
    if (!document.is_object())
        return false;
    const auto used = document.find("extensionsUsed");
    return used != document.end() && used->is_array() && std::find(used->begin(), used->end(), kMeshopt) != used->end();
}

/// Every primitive of every mesh, morph targets aside.
template <class F>
void forEachPrimitive(json& document, F&& f) {
    if (!document.contains("meshes") || !document["meshes"].is_array())
        return;
    for (json& mesh : document["meshes"])
        if (mesh.is_object() && mesh.contains("primitives") && mesh["primitives"].is_array())
            for (json& primitive : mesh["primitives"])
                if (primitive.is_object())
                    f(primitive);
}

/// Per-axis bounds of float triples.
struct Vec3Bounds {
    std::array<float, 3> min{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
    std::array<float, 3> max{-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()};
    void add(std::size_t axis, float x) {
        min[axis] = std::min(min[axis], x);
        max[axis] = std::max(max[axis], x);
    }
};

/// How compressGlb() stores a view.
enum class Packing { Raw, Attributes, Triangles, Octahedral, Exponential };

Result<GlbCompression> compress(std::string_view bytes, const std::string& name);
Result<std::string> expand(std::string_view bytes, const std::string& name);

}  // namespace

bool usesMeshoptCompression(std::string_view glb) {
    auto parsed = parseGlb(glb, "GLB");
    return parsed && listsMeshopt(parsed->document);
}

bool fileUsesMeshoptCompression(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    char header[20] = {};
    in.read(header, sizeof header);
    if (in.gcount() < 20 || std::string_view(header, 4) != "glTF" || readU32(header + 16) != kJsonChunk)
        return false;
    std::string text(std::min<std::size_t>(readU32(header + 12), kMaxJsonFileBytes), '\0');
    in.read(text.data(), std::streamsize(text.size()));
    if (std::size_t(in.gcount()) != text.size())
        return false;
    JsonIssues issues(path.string());
    const auto document = parseJsonText(text, issues);
    return document && listsMeshopt(*document);
}

// Both take JSON from the file: a member of an unexpected type (nlohmann's type_error) becomes the file's error.
Result<GlbCompression> compressGlb(std::string_view bytes, const std::string& name) {
    try {
        return compress(bytes, name);
    } catch (const nlohmann::json::exception& e) {
        return Status::error(name + ": the glTF JSON is not laid out as glTF 2.0 says (" + e.what() + ")");
    }
}

Result<std::string> expandGlb(std::string_view bytes, const std::string& name) {
    try {
        return expand(bytes, name);
    } catch (const nlohmann::json::exception& e) {
        return Status::error(name + ": the glTF JSON is not laid out as glTF 2.0 says (" + e.what() + ")");
    }
}

namespace {

Result<GlbCompression> compress(std::string_view bytes, const std::string& name) {
    auto parsed = parseGlb(bytes, name);
    if (!parsed)
        return parsed.status();
    json& document = parsed->document;
    const std::string& bin = parsed->bin;
    if (listsMeshopt(document))
        return Status::error(name + " is already compressed (" + kMeshopt + ")");
    const json& buffers = document.contains("buffers") ? document["buffers"] : json();
    if (!buffers.is_array() || buffers.size() != 1 || buffers[0].contains("uri"))
        return Status::error(name + ": only a GLB whose data all lies in its binary chunk can be compressed");
    json& views = document["bufferViews"];
    json& accessors = document["accessors"];
    if (!views.is_array() || !accessors.is_array())
        return Status::error(name + ": the GLB has no buffer views or accessors to compress");

    // What each view holds: the accessors on it must agree on one element size, start at its first byte
    // and not be sparse; indices of triangle lists and float normals get codecs of their own.
    const std::size_t viewCount = views.size();
    std::vector<std::size_t> element(viewCount, 0), users(viewCount, 0);
    std::vector<char> unsuitable(viewCount, 0);
    std::vector<Packing> packing(viewCount, Packing::Attributes);
    std::vector<std::size_t> filteredAccessor(viewCount, 0);  // the NORMAL or morph target a filter serves
    for (const json& accessor : accessors) {
        const auto v = natural(accessor, "bufferView");
        if (!v || *v >= viewCount)
            continue;
        const std::size_t size = elementBytes(accessor);
        ++users[*v];
        if (size == 0 || natural(accessor, "byteOffset").value_or(0) != 0 || accessor.contains("sparse") ||
            (element[*v] != 0 && element[*v] != size))
            unsuitable[*v] = 1;
        element[*v] = size;
    }
    // A filter rewrites a view's bytes as its accessor reads them: only for float triples alone on their view.
    auto filter = [&](std::optional<std::size_t> a, Packing how) {
        if (!a || *a >= accessors.size())
            return;
        const json& accessor = accessors[*a];
        const auto v = natural(accessor, "bufferView");
        if (v && *v < viewCount && users[*v] == 1 && natural(accessor, "componentType").value_or(0) == kFloat &&
            componentCount(accessor) == 3 && !accessor.value("normalized", false)) {
            packing[*v] = how;
            filteredAccessor[*v] = *a;
        }
    };
    forEachPrimitive(document, [&](json& primitive) {
        const std::size_t mode = natural(primitive, "mode").value_or(4);
        if (const auto a = natural(primitive, "indices"); a && *a < accessors.size()) {
            const json& accessor = accessors[*a];
            const auto v = natural(accessor, "bufferView");
            const std::size_t type = natural(accessor, "componentType").value_or(0);
            if (v && *v < viewCount && mode == 4 && (type == kUnsignedShort || type == kUnsignedInt))
                packing[*v] = Packing::Triangles;
            else if (v && *v < viewCount)
                unsuitable[*v] = 1;  // the attribute codec needs a multiple of 4 bytes; other index lists stay raw
        }
        const json& attributes = primitive.contains("attributes") ? primitive["attributes"] : json();
        filter(natural(attributes, "NORMAL"), Packing::Octahedral);
        // Morph targets: float deltas the byte codec barely shrinks; with shorter mantissas it does.
        if (primitive.contains("targets") && primitive["targets"].is_array())
            for (const json& target : primitive["targets"])
                for (const char* semantic : {"POSITION", "NORMAL"})
                    filter(natural(target, semantic), Packing::Exponential);
    });

    GlbCompression result;
    int compressedViews = 0;  // through the extension; the rest are too small to gain
    std::string packed;          // the new binary chunk: compressed views and views too small to gain
    std::size_t fallbackSize = 0;  // the decoded layout, in the placeholder buffer
    for (std::size_t v = 0; v < viewCount; ++v) {
        json& view = views[v];
        const std::size_t offset = natural(view, "byteOffset").value_or(0);
        const auto length = natural(view, "byteLength");
        if (natural(view, "buffer").value_or(1) != 0 || !length || offset > bin.size() || *length > bin.size() - offset)
            return Status::error(name + ": buffer view " + std::to_string(v) + " lies outside the binary chunk");
        const unsigned char* data = reinterpret_cast<const unsigned char*>(bin.data()) + offset;
        const std::size_t stride = element[v];
        const auto viewStride = natural(view, "byteStride");
        Packing how = packing[v];
        if (unsuitable[v] || stride == 0 || *length % stride != 0 || (viewStride && *viewStride != stride))
            how = Packing::Raw;
        if (how == Packing::Attributes && (stride % 4 != 0 || stride > 256))
            how = Packing::Raw;
        if (how == Packing::Triangles && (*length / stride) % 3 != 0)
            how = Packing::Raw;
        const std::size_t count = stride == 0 ? 0 : *length / stride;
        if (how == Packing::Exponential) {  // the filter takes finite values only: those views go losslessly
            for (std::size_t i = 0; i < 3 * count && how == Packing::Exponential; ++i) {
                float x;
                std::memcpy(&x, data + 4 * i, 4);
                if (!std::isfinite(x))
                    how = Packing::Attributes;
            }
        }
        std::vector<unsigned char> encoded;
        std::size_t decodedStride = stride;
        if (how == Packing::Triangles) {
            std::vector<unsigned int> indices(count);
            for (std::size_t i = 0; i < count; ++i) {
                if (stride == 2) {
                    std::uint16_t x;
                    std::memcpy(&x, data + 2 * i, 2);
                    indices[i] = x;
                } else {
                    std::memcpy(&indices[i], data + 4 * i, 4);
                }
            }
            const std::size_t vertices = indices.empty() ? 0 : std::size_t(*std::max_element(indices.begin(), indices.end())) + 1;
            encoded.resize(meshopt_encodeIndexBufferBound(count, vertices));
            encoded.resize(meshopt_encodeIndexBuffer(encoded.data(), encoded.size(), indices.data(), count));
        } else if (how == Packing::Octahedral) {
            std::vector<float> unit(4 * count, 0.0f);
            for (std::size_t i = 0; i < count; ++i) {
                float n[3];
                std::memcpy(n, data + 12 * i, 12);
                // The octahedral map divides by |x| + |y| + |z|: a zero or non-finite normal (glTF asks for unit
                // ones) is stored as +z rather than as whatever a division by zero makes.
                const double norm = std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
                const bool usable = std::isfinite(norm) && norm > 1e-12;
                for (int c = 0; c < 3; ++c)
                    unit[4 * i + std::size_t(c)] = usable ? float(n[c] / norm) : (c == 2 ? 1.0f : 0.0f);
            }
            decodedStride = 8;
            std::vector<unsigned char> filtered(count * decodedStride);
            meshopt_encodeFilterOct(filtered.data(), count, decodedStride, kOctahedralBits, unit.data());
            encoded.resize(meshopt_encodeVertexBufferBound(count, decodedStride));
            encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), filtered.data(), count, decodedStride));
        } else if (how == Packing::Exponential) {
            std::vector<float> values(3 * count);
            std::memcpy(values.data(), data, 12 * count);
            std::vector<unsigned char> filtered(12 * count);
            meshopt_encodeFilterExp(filtered.data(), 3 * count, 4, kExponentBits, values.data());  // decoded one by one
            encoded.resize(meshopt_encodeVertexBufferBound(count, 12));
            encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), filtered.data(), count, 12));
            // What a reader gets back: its largest change is reported, and POSITION's bounds must be its own.
            std::vector<float> decoded(3 * count);
            std::memcpy(decoded.data(), filtered.data(), 12 * count);
            meshopt_decodeFilterExp(decoded.data(), count, 12);
            json& accessor = accessors[filteredAccessor[v]];
            Vec3Bounds bounds;
            for (std::size_t i = 0; i < 3 * count; ++i) {
                result.largestChange = std::max(result.largestChange, double(std::abs(decoded[i] - values[i])));
                bounds.add(i % 3, decoded[i]);
            }
            if (accessor.contains("min") && accessor.contains("max") && count > 0) {
                accessor["min"] = bounds.min;
                accessor["max"] = bounds.max;
            }
        } else if (how == Packing::Attributes) {
            encoded.resize(meshopt_encodeVertexBufferBound(count, stride));
            encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), data, count, stride));
        }
        // Small views (a handful of keys) can grow under the codec: those stay as they are. Filtered views always
        // go through it, since only its filter turns their bytes back into vectors.
        const bool filtered = how == Packing::Octahedral || how == Packing::Exponential;
        if (how == Packing::Raw || (!filtered && encoded.size() >= *length)) {
            padTo4(packed, '\0');
            view["buffer"] = 0;
            view["byteOffset"] = packed.size();
            packed.append(reinterpret_cast<const char*>(data), *length);
            continue;
        }
        padTo4(packed, '\0');
        json extension = {{"buffer", 0},
                          {"byteOffset", packed.size()},
                          {"byteLength", encoded.size()},
                          {"byteStride", decodedStride},
                          {"count", count},
                          {"mode", how == Packing::Triangles ? "TRIANGLES" : "ATTRIBUTES"}};
        if (how == Packing::Octahedral) {
            extension["filter"] = "OCTAHEDRAL";
            view["byteStride"] = decodedStride;  // three shorts and a pad: a vertex attribute needs the stride
            json& accessor = accessors[filteredAccessor[v]];
            accessor["componentType"] = kShort;
            accessor["normalized"] = true;
            accessor.erase("min");
            accessor.erase("max");
            ++result.octahedralNormals;
        }
        if (how == Packing::Exponential)
            extension["filter"] = "EXPONENTIAL";
        packed.append(reinterpret_cast<const char*>(encoded.data()), encoded.size());
        fallbackSize = (fallbackSize + 7) / 8 * 8;
        view["buffer"] = 1;
        view["byteOffset"] = fallbackSize;
        view["byteLength"] = count * decodedStride;
        view["extensions"][kMeshopt] = std::move(extension);
        fallbackSize += count * decodedStride;
        ++compressedViews;
    }
    padTo4(packed, '\0');
    document["buffers"] = json::array({{{"byteLength", packed.size()}}});
    if (compressedViews > 0) {
        document["buffers"].push_back({{"byteLength", fallbackSize}, {"extensions", {{kMeshopt, {{"fallback", true}}}}}});
        addExtension(document, "extensionsUsed", kMeshopt);
        addExtension(document, "extensionsRequired", kMeshopt);
    }
    if (result.octahedralNormals > 0) {
        addExtension(document, "extensionsUsed", kQuantization);
        addExtension(document, "extensionsRequired", kQuantization);
    }
    result.glb = writeGlb(document, std::move(packed));
    return result;
}

Result<std::string> expand(std::string_view bytes, const std::string& name) {
    auto parsed = parseGlb(bytes, name);
    if (!parsed)
        return parsed.status();
    json& document = parsed->document;
    const std::string& bin = parsed->bin;
    json& views = document["bufferViews"];
    json& accessors = document["accessors"];
    const json buffers = document.contains("buffers") ? document["buffers"] : json::array();
    if (!views.is_array() || !accessors.is_array() || !buffers.is_array() || buffers.empty())
        return Status::error(name + ": the GLB has no buffers, buffer views or accessors");
    // Data can come from the binary chunk (buffer 0 without a URI) only: this reads one file.
    auto inBinary = [&](std::size_t buffer) { return buffer == 0 && !buffers[0].contains("uri"); };
    auto problem = [&](std::size_t v, const std::string& what) {
        return Status::error(name + ": buffer view " + std::to_string(v) + " " + what);
    };

    std::string out;
    for (std::size_t v = 0; v < views.size(); ++v) {
        json& view = views[v];
        const auto length = natural(view, "byteLength");
        if (!length || *length > kMaxExpandedBytes)
            return problem(v, "has no valid byteLength");
        std::vector<unsigned char> decoded;
        const json* extension = nullptr;
        if (view.contains("extensions") && view["extensions"].is_object() && view["extensions"].contains(kMeshopt))
            extension = &view["extensions"][kMeshopt];
        if (extension) {
            const auto source = natural(*extension, "buffer");
            const std::size_t offset = natural(*extension, "byteOffset").value_or(0);
            const auto size = natural(*extension, "byteLength");
            const auto stride = natural(*extension, "byteStride");
            const auto count = natural(*extension, "count");
            const std::string mode = extension->value("mode", std::string());
            const std::string filter = extension->value("filter", std::string("NONE"));
            if (!source || !inBinary(*source))
                return problem(v, "takes its compressed data from a buffer other than the GLB's binary chunk");
            if (!size || offset > bin.size() || *size > bin.size() - offset)
                return problem(v, "has compressed data outside the binary chunk");
            if (*length > kMaxExpansion * *size + 4096)
                return problem(v, "claims " + std::to_string(*length) + " bytes, more than its " + std::to_string(*size) +
                                      " compressed bytes can hold");
            if (!stride || !count || *stride == 0 || *stride > 256 || *count > kMaxExpandedBytes / *stride ||
                *count * *stride != *length)
                return problem(v, "has a byteStride and count that do not give its byteLength");
            const auto* input = reinterpret_cast<const unsigned char*>(bin.data()) + offset;
            decoded.resize(*length);
            int failed = 0;
            if (mode == "ATTRIBUTES") {
                if (*stride % 4 != 0)
                    return problem(v, "has an ATTRIBUTES stride that is not a multiple of 4");
                failed = meshopt_decodeVertexBuffer(decoded.data(), *count, *stride, input, *size);
            } else if (mode == "TRIANGLES" || mode == "INDICES") {
                if ((*stride != 2 && *stride != 4) || filter != "NONE" || (mode == "TRIANGLES" && *count % 3 != 0))
                    return problem(v, "has an index mode with a stride, count or filter the extension forbids");
                failed = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(decoded.data(), *count, *stride, input, *size)
                                             : meshopt_decodeIndexSequence(decoded.data(), *count, *stride, input, *size);
            } else {
                return problem(v, "has an unknown compression mode \"" + mode + "\"");
            }
            if (failed != 0)
                return problem(v, "does not decode: its compressed data is corrupt (meshoptimizer error " +
                                      std::to_string(failed) + ")");
            if (filter == "OCTAHEDRAL" && (*stride == 4 || *stride == 8))
                meshopt_decodeFilterOct(decoded.data(), *count, *stride);
            else if (filter == "QUATERNION" && *stride == 8)
                meshopt_decodeFilterQuat(decoded.data(), *count, *stride);
            else if (filter == "EXPONENTIAL" && *stride % 4 == 0)
                meshopt_decodeFilterExp(decoded.data(), *count, *stride);
            else if (filter != "NONE")
                return problem(v, "has the filter \"" + filter + "\" with a stride it does not allow");
            view["extensions"].erase(kMeshopt);
            if (view["extensions"].empty())
                view.erase("extensions");
        } else {
            const auto source = natural(view, "buffer");
            const std::size_t offset = natural(view, "byteOffset").value_or(0);
            if (!source || !inBinary(*source))
                return problem(v, "is not compressed and lies outside the GLB's binary chunk");
            if (offset > bin.size() || *length > bin.size() - offset)
                return problem(v, "lies outside the binary chunk");
            decoded.assign(bin.begin() + std::ptrdiff_t(offset), bin.begin() + std::ptrdiff_t(offset + *length));
        }
        if (out.size() + decoded.size() > kMaxExpandedBytes)
            return Status::error(name + ": decoded, its data would exceed " + std::to_string(kMaxExpandedBytes) + " bytes");
        padTo4(out, '\0');
        view["buffer"] = 0;
        view["byteOffset"] = out.size();
        out.append(reinterpret_cast<const char*>(decoded.data()), decoded.size());
    }

    // Normalized integers back to floats, each in a view of its own: normals (KHR_mesh_quantization) and skin
    // weights (core glTF, but assimp 5.2 reads 8-bit weights as garbage).
    Status dequantized = Status::success();
    auto toFloats = [&](std::size_t a) {
        json& accessor = accessors[a];
        const std::size_t type = natural(accessor, "componentType").value_or(0);
        const std::size_t components = componentCount(accessor), size = componentBytes(type);
        const auto v = natural(accessor, "bufferView");
        const auto count = natural(accessor, "count");
        if (type == kFloat || size == 0 || size == 4 || !accessor.value("normalized", false) || components == 0 || !v ||
            *v >= views.size() || !count)
            return;
        const std::size_t element = components * size, stride = natural(views[*v], "byteStride").value_or(element);
        const std::size_t start = natural(views[*v], "byteOffset").value_or(0) + natural(accessor, "byteOffset").value_or(0);
        if (*count > 0 && (stride < element || start > out.size() || (*count - 1) > (out.size() - start) / stride ||
                           start + (*count - 1) * stride + element > out.size())) {
            dequantized = Status::error(name + ": accessor " + std::to_string(a) + " reads past its buffer view");
            return;
        }
        std::vector<float> values(components * *count);
        for (std::size_t i = 0; i < *count; ++i)
            for (std::size_t c = 0; c < components; ++c) {
                const char* p = out.data() + start + i * stride + c * size;
                double x = 0.0;
                if (type == kShort || type == kUnsignedShort) {
                    std::uint16_t u;
                    std::memcpy(&u, p, 2);
                    x = type == kShort ? std::max(double(std::int16_t(u)) / 32767.0, -1.0) : double(u) / 65535.0;
                } else {
                    x = type == kByte ? std::max(double(std::int8_t(*p)) / 127.0, -1.0) : double(std::uint8_t(*p)) / 255.0;
                }
                values[components * i + c] = float(x);
            }
        padTo4(out, '\0');
        views.push_back({{"buffer", 0}, {"byteOffset", out.size()}, {"byteLength", values.size() * 4}, {"target", 34962}});
        out.append(reinterpret_cast<const char*>(values.data()), values.size() * 4);
        accessor["bufferView"] = views.size() - 1;
        accessor["componentType"] = kFloat;
        accessor.erase("normalized");
        accessor.erase("byteOffset");
    };
    forEachPrimitive(document, [&](json& primitive) {
        if (!primitive.contains("attributes") || !primitive["attributes"].is_object())
            return;
        for (const auto& [semantic, index] : primitive["attributes"].items())
            if (semantic == "NORMAL" || semantic.rfind("WEIGHTS_", 0) == 0)
                if (index.is_number_integer() && index.get<std::int64_t>() >= 0 && std::size_t(index.get<std::int64_t>()) < accessors.size() && dequantized)
                    toFloats(std::size_t(index.get<std::int64_t>()));
    });
    if (!dequantized)
        return dequantized;

    padTo4(out, '\0');
    document["buffers"] = json::array({{{"byteLength", out.size()}}});
    removeExtension(document, "extensionsUsed", kMeshopt);
    removeExtension(document, "extensionsRequired", kMeshopt);
    // KHR_mesh_quantization goes too unless some POSITION, NORMAL or TANGENT is still not float.
    bool quantized = false;
    forEachPrimitive(document, [&](json& primitive) {
        const json& attributes = primitive.contains("attributes") ? primitive["attributes"] : json();
        for (const char* semantic : {"POSITION", "NORMAL", "TANGENT"})
            if (const auto a = natural(attributes, semantic); a && *a < accessors.size())
                quantized = quantized || natural(accessors[*a], "componentType").value_or(kFloat) != kFloat;
    });
    if (!quantized) {
        removeExtension(document, "extensionsUsed", kQuantization);
        removeExtension(document, "extensionsRequired", kQuantization);
    }
    return writeGlb(document, std::move(out));
}

}  // namespace

}  // namespace softtouch::io
