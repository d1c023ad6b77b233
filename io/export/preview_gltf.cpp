#include "io/export/preview_gltf.h"

#include "io/files/json_reader.h"
#include "io/import/gltf_meshopt.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <string_view>
#include <vector>

namespace softtouch::io {

namespace fs = std::filesystem;

namespace {

/// What tinygltf's file callbacks share while one glTF loads.
struct SideFileReads {
    fs::path folder;                                  ///< The glTF's folder, canonical.
    std::string prefix;                               ///< The folder as tinygltf joins a URI to it: "<folder>/".
    std::uintmax_t bytesLeft = kMaxPreviewFileBytes;  ///< For every file the glTF names, together.
    std::string refusal;                              ///< The first file refused, and why.
};

/// The file tinygltf asks for, resolved. It asks for the folder joined to a decoded URI, then for "./" and the
/// URI (a second guess, in the working folder), which is never inside the folder unless it is the folder.
Result<fs::path> sideFileFor(const std::string& asked, SideFileReads& reads) {
    Result<fs::path> file = asked.compare(0, reads.prefix.size(), reads.prefix) == 0
                                ? resolveClipFile(reads.folder, asked.substr(reads.prefix.size()))
                                : Result<fs::path>(Status::error("is not in the glTF's folder " + reads.folder.string()));
    if (!file && reads.refusal.empty())
        reads.refusal = "\"" + asked + "\" " + file.message();
    return file;
}

bool sideFileExists(const std::string& asked, void* reads) {
    return sideFileFor(asked, *static_cast<SideFileReads*>(reads)).ok();
}

/// tinygltf's own expands "~" and "$VARIABLES" (wordexp); a URI is taken as it is.
std::string sideFilePathAsIs(const std::string& path, void*) { return path; }

bool readSideFile(std::vector<unsigned char>* out, std::string* err, const std::string& asked, void* user) {
    auto& reads = *static_cast<SideFileReads*>(user);
    const auto refuse = [&](const std::string& why) {
        if (reads.refusal.empty())
            reads.refusal = "\"" + asked + "\" " + why;
        if (err)
            *err = reads.refusal;
        return false;
    };
    auto file = sideFileFor(asked, reads);
    if (!file)
        return refuse(file.message());
    std::error_code ec;
    if (fs::file_size(file.value(), ec) > reads.bytesLeft && !ec)
        return refuse("would take the files the glTF names past " + std::to_string(kMaxPreviewFileBytes / kMiB) + " MiB together");
    auto bytes = readInputFile(file.value(), reads.bytesLeft);
    if (!bytes)
        return refuse(bytes.message());
    reads.bytesLeft -= bytes.value().size();
    out->assign(bytes.value().begin(), bytes.value().end());
    return true;
}

bool writeNoSideFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err)
        *err = "the preview writes no file";
    return false;
}

/// The page shows no image: tinygltf keeps an image's bytes as they are, so its image decoder (stb_image)
/// never runs on a file from anyone.
bool leaveImageUndecoded(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
    return true;
}

/// A string as JSON writes it (quoted, control characters escaped, bytes that are not UTF-8 replaced).
std::string jsonQuoted(const std::string& s) {
    return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// The glTF JSON of a .gltf's text or of a GLB's JSON chunk, parsed as SoftTouch parses JSON
/// (io/files/json_reader.h): tinygltf copies extras and extensions recursively, so a value 100,000 deep would
/// overflow its stack; a key given twice would be read one way here and maybe another there.
Result<nlohmann::json> gltfJsonOf(std::string_view bytes, bool binary, const std::string& name) {
    std::string_view text = bytes;
    if (binary) {
        const auto word = [&](std::size_t at) {
            std::uint32_t v = 0;
            for (int b = 3; b >= 0; --b)
                v = v << 8 | std::uint8_t(bytes[at + std::size_t(b)]);
            return std::size_t(v);
        };
        constexpr std::size_t kJsonChunk = 0x4E4F534A;  // "JSON"
        if (bytes.size() < 20 || bytes.substr(0, 4) != "glTF" || word(16) != kJsonChunk || word(12) > bytes.size() - 20)
            return Status::error(name + " is not a GLB file: it has no JSON chunk that fits in it");
        text = bytes.substr(20, word(12));
    }
    JsonIssues issues(name);
    auto document = parseJsonText(text, issues);
    if (!document || !document->is_object())
        return Status::error(issues.empty() ? name + ": the glTF JSON is not an object" : issues.summary());
    return std::move(*document);
}

/// Every buffer and image URI of `document` that is not a data: URI, through resolveClipFile, so that a
/// refusal names its place ("/buffers/0/uri"); tinygltf's own error would say "File not found".
Status checkNamedFiles(const nlohmann::json& document, const fs::path& folder, const std::string& name) {
    for (const char* kind : {"buffers", "images"}) {
        const auto list = document.find(kind);
        if (list == document.end() || !list->is_array())
            continue;
        for (std::size_t i = 0; i < list->size(); ++i) {
            const nlohmann::json& entry = (*list)[i];
            const auto uri = entry.find("uri");
            if (uri == entry.end() || !uri->is_string() || tinygltf::IsDataURI(uri->get<std::string>()))
                continue;
            const std::string raw = uri->get<std::string>();
            const std::string decoded = decodeGltfUri(raw);
            if (auto file = resolveClipFile(folder, decoded); !file)
                return Status::error(name + ": /" + kind + "/" + std::to_string(i) + "/uri: " + jsonQuoted(raw) +
                                     (decoded == raw ? "" : " (decoded " + jsonQuoted(decoded) + ")") + " " + file.message());
        }
    }
    return Status::success();
}

/// The accessor types and component types three.js's GLTFLoader reads (its WEBGL_TYPE_SIZES and
/// WEBGL_COMPONENT_TYPES); a matrix of bytes or shorts pads its columns, which this size leaves out.
struct AccessorType {
    int type;
    const char* name;
    int components;
};
constexpr std::array<AccessorType, 7> kAccessorTypes{{{TINYGLTF_TYPE_SCALAR, "SCALAR", 1},
                                                      {TINYGLTF_TYPE_VEC2, "VEC2", 2},
                                                      {TINYGLTF_TYPE_VEC3, "VEC3", 3},
                                                      {TINYGLTF_TYPE_VEC4, "VEC4", 4},
                                                      {TINYGLTF_TYPE_MAT2, "MAT2", 4},
                                                      {TINYGLTF_TYPE_MAT3, "MAT3", 9},
                                                      {TINYGLTF_TYPE_MAT4, "MAT4", 16}}};

/// Bytes of a component, 0 for a type three.js does not read (INT, DOUBLE).
std::uint64_t playableComponentBytes(int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
    }
}

/// GLTFLoader's EXTENSIONS table (web/node_modules/three/examples/jsm/loaders/GLTFLoader.js, three.js r187)
/// less KHR_binary_glTF (glTF 1.0's), KHR_draco_mesh_compression and KHR_texture_basisu: three.js plays
/// those only with a DRACOLoader or a KTX2Loader, which the page does not load. It loads the meshopt decoder.
constexpr std::array<std::string_view, 21> kPlayableExtensions{
    "KHR_lights_punctual",    "KHR_materials_clearcoat", "KHR_materials_diffuse_roughness", "KHR_materials_dispersion",
    "KHR_materials_ior",      "KHR_materials_sheen",     "KHR_materials_specular",          "KHR_materials_transmission",
    "KHR_materials_iridescence", "KHR_materials_anisotropy", "KHR_materials_unlit",         "KHR_materials_volume",
    "KHR_texture_transform",  "KHR_mesh_quantization",   "KHR_materials_emissive_strength", "EXT_materials_bump",
    "EXT_texture_webp",       "EXT_texture_avif",        "EXT_meshopt_compression",         "KHR_meshopt_compression",
    "EXT_mesh_gpu_instancing"};

}  // namespace

std::string decodeGltfUri(std::string_view uri) {
    // tinygltf's dlib::urldecode, which it applies to every URI before it looks for the file.
    const auto hex = [](char c) -> unsigned {
        if (c >= '0' && c <= '9')
            return unsigned(c - '0');
        if (c >= 'a' && c <= 'f')
            return unsigned(c - 'a' + 10);
        if (c >= 'A' && c <= 'F')
            return unsigned(c - 'A' + 10);
        return 0;
    };
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '+') {
            out += ' ';
        } else if (uri[i] == '%' && uri.size() > i + 2) {
            out += char((hex(uri[i + 1]) << 4 | hex(uri[i + 2])) & 0xFF);
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

Result<fs::path> clipFolder(const fs::path& path) {
    std::error_code ec;
    fs::path folder = fs::weakly_canonical(fs::absolute(path, ec).parent_path(), ec);
    if (ec)
        return Status::error(path.string() + ": its folder cannot be resolved (" + ec.message() + ")");
    return folder;
}

Result<fs::path> resolveClipFile(const fs::path& folder, const std::string& relative) {
    constexpr const char* kRule = "; the files a clip names must lie in its folder or below it";
    if (relative.empty())
        return Status::error("names no file");
    // A NUL would end the name early for the system, and no file SoftTouch writes has a control character.
    if (hasControlCharacter(relative))
        return Status::error("holds a control character");
    const fs::path name(relative);
    if (name.is_absolute())
        return Status::error(std::string("is an absolute path") + kRule);
    // Links and ".." resolved, then compared.
    std::error_code ec;
    const fs::path file = fs::weakly_canonical(folder / name, ec);
    if (ec)
        return Status::error("cannot be resolved (" + ec.message() + ")");
    if (!liesInside(file, folder))
        return Status::error("leads outside the clip's folder " + folder.string() + " (to " + file.string() + ")" + kRule);
    if (Status s = checkInputFile(file, kMaxPreviewFileBytes); !s)
        return s;
    const fs::path location = fs::weakly_canonical(folder / name.parent_path(), ec) / name.filename();
    if (ec)
        return Status::error("cannot be resolved (" + ec.message() + ")");
    return location;
}

Result<tinygltf::Model> readPreviewGltf(const fs::path& path) {
    const std::string name = path.string();
    auto bytes = readInputFile(path, kMaxPreviewFileBytes);
    if (!bytes)
        return Status::error(name + " " + bytes.message());
    const bool binary = path.extension() != ".gltf";
    // A compressed GLB (bake --compress) is read here decoded; the page plays it as it is (three.js decodes it).
    if (binary && usesMeshoptCompression(bytes.value())) {
        auto expanded = expandGlb(bytes.value(), name);
        if (!expanded)
            return Status::error(expanded.message());
        bytes = std::move(expanded.value());
    }
    auto folder = clipFolder(path);
    if (!folder)
        return folder.status();
    SideFileReads reads;
    reads.folder = folder.value();
    reads.prefix = reads.folder.string();
    if (reads.prefix.empty() || reads.prefix.back() != '/')
        reads.prefix += '/';
    auto document = gltfJsonOf(bytes.value(), binary, name);
    if (!document)
        return Status::error(document.message());
    if (Status s = checkNamedFiles(document.value(), reads.folder, name); !s)
        return s;

    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({&sideFileExists, &sideFilePathAsIs, &readSideFile, &writeNoSideFile, &reads});
    loader.SetImageLoader(&leaveImageUndecoded, nullptr);
    tinygltf::Model model;
    std::string error, warning;
    const std::string& data = bytes.value();
    const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &error, &warning, reinterpret_cast<const unsigned char*>(data.data()),
                                                         unsigned(data.size()), reads.folder.string())
                           : loader.LoadASCIIFromString(&model, &error, &warning, data.data(), unsigned(data.size()),
                                                        reads.folder.string());
    if (!ok) {
        std::string why = !reads.refusal.empty() ? reads.refusal : error.empty() ? warning : error;
        while (!why.empty() && (why.back() == '\n' || why.back() == ' '))
            why.pop_back();
        std::replace(why.begin(), why.end(), '\n', ' ');
        return Status::error(name + " is not a glTF file three.js can read: " + why);
    }
    if (Status s = checkPlayableGltf(model, path); !s)
        return s;
    return model;
}

Status checkPlayableGltf(const tinygltf::Model& model, const fs::path& path) {
    const std::string file = path.string() + ": ";
    const auto at = [](const std::string& pointer, std::size_t index) { return pointer + "/" + std::to_string(index); };
    // The first index found that names nothing ("/nodes/0/children/1: there is no node 9"); -1 stands for
    // "none" where glTF allows it to be absent.
    std::string problem;
    const auto refersTo = [&](const std::string& pointer, int index, std::size_t count, const char* what, bool optional = false) {
        if (problem.empty() && !(optional && index == -1) && !(index >= 0 && std::size_t(index) < count))
            problem = pointer + ": there is no " + what + " " + std::to_string(index);
    };

    // Extensions: three.js warns of one it does not know, then draws without it (or nothing).
    for (std::size_t i = 0; i < model.extensionsRequired.size(); ++i) {
        const std::string& extension = model.extensionsRequired[i];
        if (std::find(kPlayableExtensions.begin(), kPlayableExtensions.end(), extension) == kPlayableExtensions.end())
            return Status::error(file + at("/extensionsRequired", i) + ": " + jsonQuoted(extension) +
                                 " is not an extension three.js's GLTFLoader plays in the page (it plays those of its own "
                                 "table but Draco and KTX2/Basis, whose decoders the page does not load)");
    }

    // Views inside their buffers. tinygltf holds each buffer's data to its byteLength: an external or data:
    // buffer of another size is refused, and a GLB's is cut from its binary chunk, which must hold it.
    for (std::size_t v = 0; v < model.bufferViews.size(); ++v) {
        const tinygltf::BufferView& view = model.bufferViews[v];
        refersTo(at("/bufferViews", v) + "/buffer", view.buffer, model.buffers.size(), "buffer");
        if (!problem.empty())
            return Status::error(file + problem);
        const std::size_t size = model.buffers[std::size_t(view.buffer)].data.size();
        if (view.byteOffset > size || view.byteLength > size - view.byteOffset)
            return Status::error(file + at("/bufferViews", v) + ": its " + std::to_string(view.byteLength) + " bytes from byte " +
                                 std::to_string(view.byteOffset) + " lie outside buffer " + std::to_string(view.buffer) + " (" +
                                 std::to_string(size) + " bytes)");
    }

    // Accessors inside their views. `count` elements of `bytes` each, `stride` apart, from `offset`, must end
    // within the view: (count - 1)·stride + bytes <= byteLength - offset, compared without overflow.
    const auto fitsInView = [&](int v, std::uint64_t offset, std::uint64_t count, std::uint64_t bytes, std::uint64_t stride) {
        const std::uint64_t length = model.bufferViews[std::size_t(v)].byteLength;
        return count == 0 || (offset <= length && bytes <= length - offset && count - 1 <= (length - offset - bytes) / stride);
    };
    for (std::size_t a = 0; a < model.accessors.size(); ++a) {
        const tinygltf::Accessor& accessor = model.accessors[a];
        const std::string pointer = at("/accessors", a);
        const auto type = std::find_if(kAccessorTypes.begin(), kAccessorTypes.end(),
                                       [&](const AccessorType& t) { return t.type == accessor.type; });
        const std::uint64_t componentBytes = playableComponentBytes(accessor.componentType);
        if (type == kAccessorTypes.end() || componentBytes == 0)
            return Status::error(file + pointer + ": componentType " + std::to_string(accessor.componentType) +
                                 " is not one three.js reads (5120, 5121, 5122, 5123, 5125 or 5126)");
        const std::uint64_t element = std::uint64_t(type->components) * componentBytes;
        const std::string elements =
            std::to_string(accessor.count) + " " + type->name + " elements of " + std::to_string(element) + " bytes";
        if (accessor.bufferView == -1) {
            // No view: three.js allocates the elements, as zeros, before any sparse values.
            if (accessor.count > kMaxPreviewFileBytes / element)
                return Status::error(file + pointer + ": " + elements + " without a bufferView are more than " +
                                     std::to_string(kMaxPreviewFileBytes / kMiB) + " MiB of zeros");
        } else {
            refersTo(pointer + "/bufferView", accessor.bufferView, model.bufferViews.size(), "bufferView");
            if (!problem.empty())
                return Status::error(file + problem);
            const tinygltf::BufferView& view = model.bufferViews[std::size_t(accessor.bufferView)];
            if (view.byteStride != 0 && view.byteStride < element)
                return Status::error(file + pointer + ": " + elements + " do not fit bufferView " + std::to_string(accessor.bufferView) +
                                     "'s byteStride of " + std::to_string(view.byteStride));
            if (!fitsInView(accessor.bufferView, accessor.byteOffset, accessor.count, element, view.byteStride ? view.byteStride : element))
                return Status::error(file + pointer + ": " + elements + " from byte " + std::to_string(accessor.byteOffset) +
                                     (view.byteStride ? ", " + std::to_string(view.byteStride) + " bytes apart," : "") +
                                     " do not fit in bufferView " + std::to_string(accessor.bufferView) + " (" +
                                     std::to_string(view.byteLength) + " bytes)");
        }
        if (accessor.sparse.isSparse) {
            const auto& sparse = accessor.sparse;
            const std::uint64_t indexBytes = sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                                             : sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                                             : sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                                                      : 0;
            refersTo(pointer + "/sparse/indices/bufferView", sparse.indices.bufferView, model.bufferViews.size(), "bufferView");
            refersTo(pointer + "/sparse/values/bufferView", sparse.values.bufferView, model.bufferViews.size(), "bufferView");
            if (!problem.empty())
                return Status::error(file + problem);
            if (sparse.count < 1 || std::uint64_t(sparse.count) > accessor.count || indexBytes == 0 || sparse.indices.byteOffset < 0 ||
                sparse.values.byteOffset < 0 ||
                !fitsInView(sparse.indices.bufferView, std::uint64_t(sparse.indices.byteOffset), std::uint64_t(sparse.count), indexBytes, indexBytes) ||
                !fitsInView(sparse.values.bufferView, std::uint64_t(sparse.values.byteOffset), std::uint64_t(sparse.count), element, element))
                return Status::error(file + pointer + "/sparse: its " + std::to_string(sparse.count) +
                                     " indices (unsigned byte, short or int) and values must fit in their bufferViews, and be at "
                                     "least 1 and at most the accessor's count (" + std::to_string(accessor.count) + ")");
        }
    }

    // Everything else an index names.
    for (std::size_t m = 0; m < model.meshes.size(); ++m)
        for (std::size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            const tinygltf::Primitive& primitive = model.meshes[m].primitives[p];
            const std::string pointer = at(at("/meshes", m) + "/primitives", p);
            for (const auto& [attribute, accessor] : primitive.attributes)
                refersTo(pointer + "/attributes/" + attribute, accessor, model.accessors.size(), "accessor");
            refersTo(pointer + "/indices", primitive.indices, model.accessors.size(), "accessor", true);
            refersTo(pointer + "/material", primitive.material, model.materials.size(), "material", true);
            for (std::size_t t = 0; t < primitive.targets.size(); ++t)
                for (const auto& [attribute, accessor] : primitive.targets[t])
                    refersTo(at(pointer + "/targets", t) + "/" + attribute, accessor, model.accessors.size(), "accessor");
        }
    for (std::size_t n = 0; n < model.nodes.size(); ++n) {
        const tinygltf::Node& node = model.nodes[n];
        refersTo(at("/nodes", n) + "/mesh", node.mesh, model.meshes.size(), "mesh", true);
        refersTo(at("/nodes", n) + "/skin", node.skin, model.skins.size(), "skin", true);
        refersTo(at("/nodes", n) + "/camera", node.camera, model.cameras.size(), "camera", true);
        for (std::size_t c = 0; c < node.children.size(); ++c)
            refersTo(at(at("/nodes", n) + "/children", c), node.children[c], model.nodes.size(), "node");
    }
    for (std::size_t s = 0; s < model.skins.size(); ++s) {
        const tinygltf::Skin& skin = model.skins[s];
        refersTo(at("/skins", s) + "/inverseBindMatrices", skin.inverseBindMatrices, model.accessors.size(), "accessor", true);
        refersTo(at("/skins", s) + "/skeleton", skin.skeleton, model.nodes.size(), "node", true);
        for (std::size_t j = 0; j < skin.joints.size(); ++j)
            refersTo(at(at("/skins", s) + "/joints", j), skin.joints[j], model.nodes.size(), "node");
    }
    for (std::size_t a = 0; a < model.animations.size(); ++a) {
        const tinygltf::Animation& animation = model.animations[a];
        for (std::size_t s = 0; s < animation.samplers.size(); ++s) {
            refersTo(at(at("/animations", a) + "/samplers", s) + "/input", animation.samplers[s].input, model.accessors.size(), "accessor");
            refersTo(at(at("/animations", a) + "/samplers", s) + "/output", animation.samplers[s].output, model.accessors.size(), "accessor");
        }
        for (std::size_t c = 0; c < animation.channels.size(); ++c) {
            const std::string pointer = at(at("/animations", a) + "/channels", c);
            refersTo(pointer + "/sampler", animation.channels[c].sampler, animation.samplers.size(), "sampler in the animation");
            refersTo(pointer + "/target/node", animation.channels[c].target_node, model.nodes.size(), "node", true);
        }
    }
    for (std::size_t t = 0; t < model.textures.size(); ++t) {
        refersTo(at("/textures", t) + "/source", model.textures[t].source, model.images.size(), "image", true);
        refersTo(at("/textures", t) + "/sampler", model.textures[t].sampler, model.samplers.size(), "sampler", true);
    }
    for (std::size_t m = 0; m < model.materials.size(); ++m) {
        const tinygltf::Material& material = model.materials[m];
        const std::string pointer = at("/materials", m);
        const std::size_t textures = model.textures.size();
        refersTo(pointer + "/pbrMetallicRoughness/baseColorTexture/index", material.pbrMetallicRoughness.baseColorTexture.index, textures, "texture", true);
        refersTo(pointer + "/pbrMetallicRoughness/metallicRoughnessTexture/index",
                 material.pbrMetallicRoughness.metallicRoughnessTexture.index, textures, "texture", true);
        refersTo(pointer + "/normalTexture/index", material.normalTexture.index, textures, "texture", true);
        refersTo(pointer + "/occlusionTexture/index", material.occlusionTexture.index, textures, "texture", true);
        refersTo(pointer + "/emissiveTexture/index", material.emissiveTexture.index, textures, "texture", true);
    }
    for (std::size_t s = 0; s < model.scenes.size(); ++s)
        for (std::size_t r = 0; r < model.scenes[s].nodes.size(); ++r)
            refersTo(at(at("/scenes", s) + "/nodes", r), model.scenes[s].nodes[r], model.nodes.size(), "node");
    refersTo("/scene", model.defaultScene, model.scenes.size(), "scene", true);
    if (!problem.empty())
        return Status::error(file + problem);

    // A forest: one parent at most, then every node reachable from a root (a node without a parent). A node
    // that is not lies on a cycle or below one, and so does its first ancestor seen twice. three.js follows
    // the children as they are, and a cycle never ends.
    const std::size_t nodeCount = model.nodes.size();
    std::vector<int> parent(nodeCount, -1);
    for (std::size_t n = 0; n < nodeCount; ++n)
        for (std::size_t c = 0; c < model.nodes[n].children.size(); ++c) {
            const int child = model.nodes[n].children[c];
            if (parent[std::size_t(child)] != -1)
                return Status::error(file + at(at("/nodes", n) + "/children", c) + ": node " + std::to_string(child) +
                                     " is already a child of node " + std::to_string(parent[std::size_t(child)]) +
                                     " (glTF's nodes form trees: one parent each)");
            parent[std::size_t(child)] = int(n);
        }
    std::vector<bool> reached(nodeCount, false);
    std::vector<int> pending;
    for (std::size_t n = 0; n < nodeCount; ++n)
        if (parent[n] == -1)
            pending.push_back(int(n));
    while (!pending.empty()) {
        const int n = pending.back();
        pending.pop_back();
        reached[std::size_t(n)] = true;
        for (const int child : model.nodes[std::size_t(n)].children)
            pending.push_back(child);
    }
    const auto unreached = std::find(reached.begin(), reached.end(), false);
    if (unreached != reached.end()) {
        std::vector<bool> seen(nodeCount, false);
        std::size_t n = std::size_t(unreached - reached.begin());
        while (!seen[n]) {
            seen[n] = true;
            n = std::size_t(parent[n]);
        }
        return Status::error(file + at("/nodes", n) + ": node " + std::to_string(n) +
                             " is its own ancestor (its children lead back to it; glTF's nodes form trees)");
    }
    for (std::size_t s = 0; s < model.scenes.size(); ++s)
        for (std::size_t r = 0; r < model.scenes[s].nodes.size(); ++r) {
            const int root = model.scenes[s].nodes[r];
            if (parent[std::size_t(root)] != -1)
                return Status::error(file + at(at("/scenes", s) + "/nodes", r) + ": node " + std::to_string(root) +
                                     " is a child of node " + std::to_string(parent[std::size_t(root)]) + ", not a root");
        }
    return Status::success();
}

}  // namespace softtouch::io
