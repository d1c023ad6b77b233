#include "io/pipeline/clip_preview.h"

#include "io/export/lattice_cache.h"
#include "io/export/preview_gltf.h"
#include "io/files/input_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace softtouch::io {

namespace fs = std::filesystem;

namespace {

std::string base64(std::string_view bytes) {
    static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const std::uint32_t v = std::uint32_t(std::uint8_t(bytes[i])) << 16 | std::uint32_t(std::uint8_t(bytes[i + 1])) << 8 |
                                std::uint8_t(bytes[i + 2]);
        out += kDigits[v >> 18];
        out += kDigits[(v >> 12) & 63];
        out += kDigits[(v >> 6) & 63];
        out += kDigits[v & 63];
    }
    if (i < bytes.size()) {
        const bool two = i + 1 < bytes.size();
        const std::uint32_t v = std::uint32_t(std::uint8_t(bytes[i])) << 16 | (two ? std::uint32_t(std::uint8_t(bytes[i + 1])) << 8 : 0);
        out += kDigits[v >> 18];
        out += kDigits[(v >> 12) & 63];
        out += two ? kDigits[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

/// readInputFile with the file's name in front of its error ("x.exr does not exist").
Result<std::string> readFile(const fs::path& path, std::uintmax_t maxBytes) {
    auto bytes = readInputFile(path, maxBytes);
    if (!bytes)
        return Status::error(path.string() + " " + bytes.message());
    return bytes;
}

bool endsWith(const std::string& s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// ---- glTF ----

/// Bounds of every primitive's POSITION (glTF requires their min and max).
Result<Bounds> positionBounds(const tinygltf::Model& model, const fs::path& path) {
    Bounds b{Vec3::Constant(1e300), Vec3::Constant(-1e300)};
    int found = 0;
    for (const auto& mesh : model.meshes)
        for (const auto& primitive : mesh.primitives) {
            const auto it = primitive.attributes.find("POSITION");
            if (it == primitive.attributes.end() || it->second < 0 || it->second >= int(model.accessors.size()))
                continue;
            const auto& accessor = model.accessors[std::size_t(it->second)];
            if (accessor.minValues.size() != 3 || accessor.maxValues.size() != 3)
                return Status::error(path.string() + ": mesh '" + mesh.name + "' has a POSITION without min and max");
            for (int k = 0; k < 3; ++k) {
                b.min[k] = std::min(b.min[k], accessor.minValues[std::size_t(k)]);
                b.max[k] = std::max(b.max[k], accessor.maxValues[std::size_t(k)]);
            }
            ++found;
        }
    if (found == 0 || !b.min.allFinite() || !b.max.allFinite())
        return Status::error(path.string() + " has no mesh positions to show");
    return b;
}

/// The rest bounds of the glTF mesh at `path` (a VAT's or a lattice cache's mesh).
Result<Bounds> meshFileBounds(const fs::path& path) {
    auto model = readPreviewGltf(path);
    if (!model)
        return Status::error(model.message());
    return positionBounds(model.value(), path);
}

/// Frames and rate of the first animation: one key per frame (as SoftTouch writes them).
Status readAnimationTiming(const tinygltf::Model& model, const fs::path& path, PreviewClip& clip) {
    if (model.animations.empty() || model.animations[0].samplers.empty())
        return Status::error(path.string() + " has no animation to play");
    const int input = model.animations[0].samplers[0].input;
    if (input < 0 || input >= int(model.accessors.size()))
        return Status::error(path.string() + ": animation 0 has no key times");
    const auto& times = model.accessors[std::size_t(input)];
    const int keys = int(times.count);
    const double last = times.maxValues.empty() ? 0.0 : times.maxValues[0];
    clip.fps = keys > 1 && last > 0.0 ? std::round(1000.0 * double(keys - 1) / last) / 1000.0 : 24.0;
    // A loop's closing key is frame 0 again, one frame on (ClipSetup::loops): not a frame of its own.
    const tinygltf::Value& extras = model.animations[0].extras;
    clip.closesLoop = keys > 1 && extras.IsObject() && extras.Has("loopClosingKey") && extras.Get("loopClosingKey").IsBool() &&
                      extras.Get("loopClosingKey").Get<bool>();
    clip.frames = clip.closesLoop ? keys - 1 : keys;
    if (clip.frames < 1 || !std::isfinite(clip.fps) || clip.fps <= 0.0)
        return Status::error(path.string() + ": animation 0 has no usable key times");
    return Status::success();
}

/// The glTF's own external files (buffers that are not data: URIs), resolved as tinygltf read them
/// (readPreviewGltf): the page embeds them. The page finds a file by its name, so two of one name are refused.
Status addExternalBuffers(const tinygltf::Model& model, const fs::path& path, PreviewClip& clip) {
    auto folder = clipFolder(path);
    if (!folder)
        return folder.status();
    for (std::size_t i = 0; i < model.buffers.size(); ++i) {
        const std::string& uri = model.buffers[i].uri;
        if (uri.empty() || tinygltf::IsDataURI(uri))
            continue;
        auto file = resolveClipFile(folder.value(), decodeGltfUri(uri));
        if (!file)
            return Status::error(path.string() + ": /buffers/" + std::to_string(i) + "/uri: \"" + uri + "\" " + file.message());
        for (const fs::path& other : clip.files)
            if (std::error_code ec; other.filename() == file.value().filename() && !fs::equivalent(other, file.value(), ec))
                return Status::error(path.string() + ": /buffers/" + std::to_string(i) + "/uri: \"" + uri + "\" has the name of " +
                                     other.string() + ", another file the page holds (the page finds files by name)");
        clip.files.push_back(file.value());
    }
    return Status::success();
}

Result<PreviewClip> inspectGltf(const fs::path& path) {
    auto model = readPreviewGltf(path);
    if (!model)
        return Status::error(model.message());
    const tinygltf::Model& m = model.value();
    PreviewClip clip;
    clip.name = clip.main = path.filename().string();
    clip.files.push_back(path);
    if (Status s = addExternalBuffers(m, path, clip); !s)
        return s;
    auto bounds = positionBounds(m, path);
    if (!bounds)
        return Status::error(bounds.message());
    clip.restBounds = bounds.value();
    std::size_t targets = 0;
    for (const auto& mesh : m.meshes)
        for (const auto& primitive : mesh.primitives)
            targets = std::max(targets, primitive.targets.size());
    if (!m.skins.empty()) {
        clip.kind = PreviewKind::Skinned;
        clip.summary = "skinned, " + std::to_string(m.skins[0].joints.size()) + " bones";
    } else if (targets > 0) {
        clip.kind = PreviewKind::Morph;
        clip.summary = std::to_string(targets) + " morph targets";
    } else {
        return Status::error(path.string() + " has neither a skin nor morph targets: nothing in it moves");
    }
    if (Status s = readAnimationTiming(m, path, clip); !s)
        return s;
    return clip;
}

// ---- VAT ----

Result<PreviewClip> inspectVat(const fs::path& json) {
    auto text = readFile(json, kMaxJsonFileBytes);
    if (!text)
        return Status::error(text.message());
    nlohmann::json j = nlohmann::json::parse(text.value(), nullptr, false);
    if (j.is_discarded() || !j.is_object() || j.value("format", "") != "softtouch-vat")
        return Status::error(json.string() + " is not a SoftTouch VAT description (format \"softtouch-vat\")");
    PreviewClip clip;
    clip.kind = PreviewKind::Vat;
    clip.name = json.filename().string();
    auto field = [&](const char* key) -> const nlohmann::json* {
        const auto it = j.find(key);
        return it == j.end() ? nullptr : &*it;
    };
    const auto* frames = field("frameCount");
    const auto* fps = field("fps");
    const auto* step = field("frameRowStep");
    for (const auto& [key, value] : {std::pair{"frameCount", frames}, {"fps", fps}, {"frameRowStep", step}})
        if (!value || !value->is_number() || !(value->get<double>() > 0.0))
            return Status::error(json.string() + ": /" + key + " must be a positive number");
    clip.frames = frames->get<int>();
    clip.fps = fps->get<double>();
    nlohmann::json data = {{"frameRowStep", step->get<double>()}};
    auto folder = clipFolder(json);
    if (!folder)
        return folder.status();
    for (const char* key : {"mesh", "positionTexture", "normalTexture"}) {
        const auto* name = field(key);
        if (!name || !name->is_string() || name->get<std::string>().empty() ||
            fs::path(name->get<std::string>()).filename() != fs::path(name->get<std::string>()))
            return Status::error(json.string() + ": /" + key + " must name a file beside it");
        // Beside it, and no link out of its folder (the page would carry what it points to).
        auto file = resolveClipFile(folder.value(), name->get<std::string>());
        if (!file)
            return Status::error(json.string() + ": /" + key + ": \"" + name->get<std::string>() + "\" " + file.message());
        data[key] = name->get<std::string>();
        clip.files.push_back(file.value());
    }
    clip.main = data["mesh"].get<std::string>();
    clip.files.insert(clip.files.begin(), json);
    auto bounds = meshFileBounds(clip.files[1]);
    if (!bounds)
        return Status::error(bounds.message());
    clip.restBounds = bounds.value();
    clip.summary = "vertex animation textures, " + std::to_string(j.value("vertexCount", 0)) + " vertices";
    clip.kindData = data.dump();
    return clip;
}

// ---- lattice cache ----

Result<PreviewClip> inspectLattice(const fs::path& bin) {
    auto cache = readLatticeCache(bin);
    if (!cache)
        return Status::error(cache.message());
    const LatticeCache& c = cache.value();
    PreviewClip clip;
    clip.kind = PreviewKind::Lattice;
    clip.name = bin.filename().string();
    clip.main = c.mesh;
    clip.frames = int(c.frameCount);
    clip.fps = c.fps;
    auto folder = clipFolder(bin);
    if (!folder)
        return folder.status();
    auto mesh = resolveClipFile(folder.value(), c.mesh);
    if (!mesh)
        return Status::error(bin.string() + ": /mesh: \"" + c.mesh + "\" " + mesh.message());
    clip.files = {bin, mesh.value()};
    auto bounds = meshFileBounds(clip.files[1]);
    if (!bounds)
        return Status::error(bounds.message());
    clip.restBounds = bounds.value();
    std::size_t nodesPerFrame = 0;
    nlohmann::json objects = nlohmann::json::array();
    for (std::size_t o = 0; o < c.objects.size(); ++o) {
        const LatticeCacheObject& object = c.objects[o];
        std::vector<double> axes;
        for (int col = 0; col < 3; ++col)
            for (int row = 0; row < 3; ++row)
                axes.push_back(object.box.axes(row, col));
        objects.push_back({{"primitive", o},
                           {"nodes", object.nodes},
                           {"degrees", object.degrees},
                           {"firstNode", nodesPerFrame},
                           {"boxAxes", axes},
                           {"boxSize", {object.box.size.x(), object.box.size.y(), object.box.size.z()}}});
        nodesPerFrame += std::size_t(object.nodeCount());
    }
    const nlohmann::json data = {{"mesh", c.mesh},
                                 {"nodesFile", clip.name},
                                 {"nodeDataOffset", c.nodeDataOffset},
                                 {"nodesPerFrame", nodesPerFrame},
                                 {"nodeCount", nodesPerFrame * c.frameCount},
                                 {"objects", objects}};
    clip.kindData = data.dump();
    clip.summary = "lattice cache, " + std::to_string(nodesPerFrame) + " nodes a frame";
    return clip;
}

// ---- three.js modules ----

/// The package path a specifier names, from the module at `from` (a package path, or empty for the
/// player); empty when it is not one of three's.
std::string resolveSpecifier(const std::string& specifier, const std::string& from) {
    if (specifier == "three")
        return "build/three.module.js";
    if (specifier.rfind("three/addons/", 0) == 0)
        return "examples/jsm/" + specifier.substr(13);
    if (!from.empty() && (specifier.rfind("./", 0) == 0 || specifier.rfind("../", 0) == 0))
        return (fs::path(from).parent_path() / specifier).lexically_normal().generic_string();
    return {};
}

/// Where the quoted specifier after the keyword at `k` (of length `length`) starts, or npos: the keyword
/// must be a word of its own and the next non-blank character a quote.
std::size_t specifierQuote(const std::string& line, std::size_t k, std::size_t length) {
    const auto partOfWord = [](char c) { return std::isalnum(std::uint8_t(c)) || c == '_' || c == '$' || c == '.'; };
    if (k > 0 && partOfWord(line[k - 1]))
        return std::string::npos;
    const std::size_t q = line.find_first_not_of(" \t", k + length);
    return q != std::string::npos && (line[q] == '\'' || line[q] == '"') ? q : std::string::npos;
}

/// Rewrites the static imports of `source` (`… from '…'`, `import '…'`; comment lines are left alone) to
/// map names, collecting the package paths they name. Specifiers that are not three's stay as they are.
std::string rewriteImports(const std::string& source, const std::string& from, std::vector<std::string>& named) {
    std::string out;
    out.reserve(source.size() + 1024);
    std::istringstream lines(source);
    std::string line;
    while (std::getline(lines, line)) {
        const std::size_t first = line.find_first_not_of(" \t");
        const bool comment = first != std::string::npos && (line[first] == '*' || line.compare(first, 2, "//") == 0 ||
                                                             line.compare(first, 2, "/*") == 0);
        std::vector<std::size_t> quotes;
        if (!comment && first != std::string::npos && line.compare(first, 6, "import") == 0)
            if (const std::size_t q = specifierQuote(line, first, 6); q != std::string::npos)
                quotes.push_back(q);
        for (std::size_t k = comment ? std::string::npos : line.find("from"); k != std::string::npos; k = line.find("from", k + 4))
            if (const std::size_t q = specifierQuote(line, k, 4); q != std::string::npos)
                quotes.push_back(q);
        // Right to left, so earlier positions stay valid as specifiers change length.
        std::sort(quotes.rbegin(), quotes.rend());
        for (const std::size_t q : quotes) {
            const std::size_t end = line.find(line[q], q + 1);
            if (end == std::string::npos)
                continue;
            const std::string path = resolveSpecifier(line.substr(q + 1, end - q - 1), from);
            if (path.empty())
                continue;
            line.replace(q + 1, end - q - 1, "three/" + path);
            named.push_back(path);
        }
        out += line;
        out += '\n';
    }
    return out;
}

}  // namespace

bool previewPlays(std::string_view format) {
    for (std::string_view played : {"skin", "pca", "glb", "gltf", "vat", "lattice"})
        if (format == played)
            return true;
    return false;
}

const char* previewKindName(PreviewKind kind) {
    switch (kind) {
    case PreviewKind::Skinned: return "skinned";
    case PreviewKind::Morph: return "morph";
    case PreviewKind::Vat: return "vat";
    case PreviewKind::Lattice: return "lattice";
    }
    return "morph";
}

Result<InlinedModules> inlineThreeModules(const std::string& script, const fs::path& threeRoot) {
    if (!fs::is_regular_file(threeRoot / "build/three.module.js"))
        return Status::error("three.js is not installed at " + threeRoot.string() +
                             " (the preview page needs the npm package web/package.json names: run bash "
                             "scripts/install-deps.sh)");
    InlinedModules result;
    std::vector<std::string> pending;
    result.script = rewriteImports(script, "", pending);
    nlohmann::json imports = nlohmann::json::object();
    std::set<std::string> done;
    while (!pending.empty()) {
        const std::string path = pending.back();
        pending.pop_back();
        if (!done.insert(path).second)
            continue;
        auto source = readFile(threeRoot / path, 64 * kMiB);
        if (!source)
            return Status::error("three.js module: " + source.message());
        imports["three/" + path] = "data:text/javascript;base64," + base64(rewriteImports(source.value(), path, pending));
    }
    result.moduleCount = int(done.size());
    result.importMapJson = nlohmann::json{{"imports", imports}}.dump();
    return result;
}

Result<PreviewClip> inspectPreviewClip(const fs::path& path) {
    const std::string s = path.string();
    for (const char* suffix : {".vat.json", ".vat-mesh.glb", ".vat-position.exr", ".vat-normal.exr"})
        if (endsWith(s, suffix))
            return inspectVat(fs::path(s.substr(0, s.size() - std::string_view(suffix).size()) + ".vat.json"));
    for (const char* suffix : {".lattice.bin", ".lattice.glb"})
        if (endsWith(s, suffix))
            return inspectLattice(fs::path(s.substr(0, s.size() - std::string_view(suffix).size()) + ".lattice.bin"));
    if (endsWith(s, ".glb") || endsWith(s, ".gltf"))
        return inspectGltf(path);
    // A base path, as `bake --format vat|lattice` takes it.
    std::error_code ec;
    if (fs::exists(s + ".vat.json", ec))
        return inspectVat(s + ".vat.json");
    if (fs::exists(s + ".lattice.bin", ec))
        return inspectLattice(s + ".lattice.bin");
    return Status::error(s + " is not a clip the preview plays: give a skinned or morph .glb/.gltf, a VAT's "
                             ".vat.json or a lattice cache's .lattice.bin (or their base path)");
}

Result<std::string> buildPreviewPage(const PreviewClip& clip, const PreviewCamera& camera, const PreviewAssets& assets) {
    auto player = readFile(assets.webRoot / "preview.js", 16 * kMiB);
    if (!player)
        return Status::error("the preview player: " + player.message());
    auto modules = inlineThreeModules(player.value(), assets.webRoot / "node_modules/three");
    if (!modules)
        return Status::error(modules.message());
    nlohmann::json page = {
        {"kind", previewKindName(clip.kind)},
        {"name", clip.name},
        {"main", clip.main},
        {"frames", clip.frames},
        {"fps", clip.fps},
        {"loop", clip.loop},
        {"closesLoop", clip.closesLoop},
        {"summary", clip.summary},
        {"camera",
         {{"eye", camera.eye},
          {"centre", camera.centre},
          {"up", camera.up},
          {"fovYDegrees", camera.fovYDegrees},
          {"near", camera.nearPlane},
          {"far", camera.farPlane}}},
    };
    std::set<std::string> names;
    nlohmann::json files = nlohmann::json::object();
    for (const fs::path& file : clip.files) {
        const std::string name = file.filename().string();
        if (!names.insert(name).second)
            continue;
        auto bytes = readFile(file, kMaxPreviewFileBytes);
        if (!bytes)
            return Status::error(bytes.message());
        files[name] = base64(bytes.value());
    }
    page["files"] = std::move(files);
    if (clip.kind == PreviewKind::Vat || clip.kind == PreviewKind::Lattice) {
        const char* shader = clip.kind == PreviewKind::Vat ? "vat_deform.glsl" : "lattice_deform.glsl";
        auto source = readFile(assets.shaderDir / shader, kMiB);
        if (!source)
            return Status::error("the engine shader: " + source.message());
        page["shaders"] = {{clip.kind == PreviewKind::Vat ? "vat" : "lattice", source.value()}};
        page[clip.kind == PreviewKind::Vat ? "vat" : "lattice"] = nlohmann::json::parse(clip.kindData);
    }
    // Inside <script>, "</" would end the element early; "<\/" is the same JSON string.
    std::string json = page.dump();
    for (std::size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 3))
        json.replace(at, 2, "<\\/");
    std::string html;
    html.reserve(json.size() + modules.value().importMapJson.size() + 8192);
    html += "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>SoftTouch preview: ";
    html += clip.name;
    html += "</title>\n<style>\n"
            "html, body { margin: 0; height: 100%; overflow: hidden; background: #5f6066; font: 14px sans-serif; }\n"
            "#view canvas { display: block; }\n"
            "#bar { position: fixed; left: 0; right: 0; bottom: 0; display: flex; gap: 10px; align-items: center;"
            " padding: 8px 12px; background: rgba(20, 20, 24, 0.7); color: #eee; }\n"
            "#frame { flex: 1; }\n"
            "#status { position: fixed; top: 10px; left: 12px; color: #fdd; }\n"
            "body.still #bar { display: none; }\n"
            "#readback { display: none; }\n"
            "</style>\n<script type=\"importmap\">";
    html += modules.value().importMapJson;
    html += "</script>\n</head>\n<body>\n<div id=\"view\"></div>\n<div id=\"status\"></div>\n"
            "<div id=\"bar\"><button id=\"play\">Play</button><input id=\"frame\" type=\"range\" min=\"0\" value=\"0\">"
            "<span id=\"label\"></span><button id=\"reset\" title=\"Back to the render's camera\">Reset view</button></div>\n"
            "<pre id=\"readback\"></pre>\n<script type=\"application/json\" id=\"softtouch-clip\">";
    html += json;
    html += "</script>\n<script>if (location.hash.includes('frame=')) document.body.className = 'still';</script>\n"
            "<script type=\"module\">\n";
    html += modules.value().script;
    html += "</script>\n</body>\n</html>\n";
    return html;
}

}  // namespace softtouch::io
