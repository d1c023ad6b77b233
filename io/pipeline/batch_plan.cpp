#include "io/pipeline/batch_plan.h"

#include "io/documents/preset_file.h"
#include "io/documents/project_file.h"
#include "io/export/export_formats.h"
#include "io/files/atomic_file.h"
#include "io/files/content_hash.h"
#include "io/files/input_file.h"
#include "io/files/json_reader.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

namespace softtouch::io {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "softtouch-batch";
constexpr const char* kStampFormat = "softtouch-batch-stamp";
/// "pc2, mdd, …, lattice, mp4 or gif".
std::string knownFormats() { return exportFormatNames(", ", ", ") + ", mp4 or gif"; }

/// The extension a job's output gets: its export's first (none for a base path, vat and lattice), or
/// the video's.
std::string extensionOf(const std::string& format) {
    if (isVideoFormat(format))
        return "." + format;
    const std::vector<std::string_view> extensions = extensionsOf(*findExportFormat(format));
    return extensions.empty() ? std::string() : std::string(extensions.front());
}

Status hashFile(const fs::path& path, ContentHash& hash) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return Status::error("cannot read '" + path.string() + "'");
    char buffer[1 << 16];
    while (in) {
        in.read(buffer, sizeof buffer);
        hash.add(buffer, std::size_t(in.gcount()));
    }
    return Status::success();
}

/// A job id part: letters, digits, '-' and '_' kept, anything else '_'.
std::string slug(const std::string& text) {
    std::string s;
    for (char c : text)
        s += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
    return s.empty() ? "_" : s;
}

/// A path named relative to a folder stays in it: not absolute, and no ".." part climbs out.
bool staysBelow(const fs::path& relative) {
    return !relative.is_absolute() &&
           std::none_of(relative.begin(), relative.end(), [](const fs::path& part) { return part == ".."; });
}

/// Most jobs one manifest may expand to: each is a stamp file and a line of jobs.txt; a product of a
/// million outputs is a typo, not a library.
constexpr double kMaxBatchJobs = 1e6;

std::vector<fs::path> pathList(const JsonValue& v, const fs::path& base, bool required) {
    std::vector<fs::path> paths;
    if (!v.exists()) {
        if (required)
            v.problem("expected an array of file paths");
        return paths;
    }
    if (!v.isArray() || (required && v.size() == 0)) {
        v.problem(required ? "expected a non-empty array of file paths" : "expected an array of file paths");
        return paths;
    }
    for (std::size_t i = 0; i < v.size(); ++i) {
        const auto s = v.at(i).string(true);
        if (!s)
            continue;
        if (s->empty() || hasControlCharacter(*s)) {
            v.at(i).problem(s->empty() ? "expected a file path, got an empty string"
                                       : "a file path must not hold control characters (a newline, a NUL, ...)");
            continue;
        }
        const fs::path path = fs::path(*s).is_absolute() ? fs::path(*s) : (base / *s).lexically_normal();
        // The file's stem names its part of every output ({scene}, {preset}): it must give a name.
        if (const std::string name = libraryName(path.stem().string()); name.find_first_not_of('.') == std::string::npos) {
            v.at(i).problem("the file name \"" + path.filename().string() + "\" gives no name for the library's outputs "
                            "(its stem is \"" + path.stem().string() + "\"): rename the file");
            continue;
        }
        paths.push_back(path);
    }
    return paths;
}


}  // namespace

std::string libraryName(const std::string& text) {
    std::string name;
    for (char c : text)
        name += (std::isalnum(static_cast<unsigned char>(c)) && static_cast<unsigned char>(c) < 0x80) || c == '.' || c == '-' ||
                        c == '_'
                    ? c
                    : '_';
    return name;
}

std::string hashText(std::uint64_t hash) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
    return text;
}

bool isVideoFormat(std::string_view format) { return format == "mp4" || format == "gif"; }

namespace {

/// The manifest, or nothing with every problem in `issues`.
std::optional<BatchManifest> readBatchManifest(const fs::path& path, JsonIssues& issues) {
    const auto doc = parseJsonFile(path.string(), issues);
    if (!doc)
        return std::nullopt;
    const JsonValue root(&*doc, "", &issues);
    if (!root.expectObject(true))
        return std::nullopt;
    if (const auto format = root["format"].string(true); format && *format != kFormat)
        root["format"].problem(std::string("expected \"") + kFormat + "\", got \"" + *format + "\"");
    if (const auto version = root["version"].integer(1, 1000000, true); version && *version > kBatchManifestVersion)
        root["version"].problem("version " + std::to_string(*version) + " was written by a newer SoftTouch; this build reads up to " +
                                std::to_string(kBatchManifestVersion));
    if (!issues.empty())  // not a manifest this build reads: its other keys mean nothing here
        return std::nullopt;
    root.checkKeys({"format", "version", "scenes", "presets", "clips", "formats", "frames", "compress", "video",
                    "outputRoot", "output", "resources"});

    BatchManifest m;
    m.path = fs::absolute(path);
    const fs::path base = m.path.parent_path();
    m.scenes = pathList(root["scenes"], base, true);
    m.presets = pathList(root["presets"], base, false);
    if (const JsonValue clips = root["clips"]; clips.exists()) {
        if (!clips.isArray())
            clips.problem("expected an array of clip names");
        for (std::size_t i = 0; i < clips.size(); ++i)
            if (auto s = clips.at(i).string(true)) {
                if (s->empty())
                    clips.at(i).problem("expected a clip name, got an empty string");
                else if (s->find_first_of("/\\") != std::string::npos || s->find_first_not_of('.') == std::string::npos ||
                         hasControlCharacter(*s))
                    clips.at(i).problem("expected a clip name, not a path (\"" + shownName(*s) +
                                        "\" has '/', '\\', only dots or control characters)");
                else
                    m.clips.push_back(*s);
            }
    }
    const JsonValue formats = root["formats"];
    if (!formats.isArray() || formats.size() == 0)
        formats.problem("expected a non-empty array of formats (" + knownFormats() + ")");
    for (std::size_t i = 0; i < formats.size(); ++i)
        if (auto s = formats.at(i).string(true)) {
            // Names as the registry writes them (lower case): a job's id and output name carry them.
            const bool lowerCase = std::none_of(s->begin(), s->end(), [](unsigned char c) { return std::isupper(c); });
            if (!lowerCase || (!findExportFormat(*s) && !isVideoFormat(*s)))
                formats.at(i).problem("unknown format \"" + *s + "\" (expected " + knownFormats() + ")");
            else if (std::find(m.formats.begin(), m.formats.end(), *s) != m.formats.end())
                formats.at(i).problem("\"" + *s + "\" is listed twice");
            else
                m.formats.push_back(*s);
        }
    if (auto f = root["frames"].integer(1, 1000000))
        m.frames = *f;
    if (auto c = root["compress"].boolean()) {
        m.compress = *c;
        const bool packable = std::any_of(m.formats.begin(), m.formats.end(), [](const std::string& f) {
            const ExportFormat* format = findExportFormat(f);
            return format && format->takesCompress;
        });
        if (*c && !packable)
            root["compress"].problem("packs glb, pca and skin outputs, and the formats list none of them");
    }
    if (const JsonValue video = root["video"]; video.expectObject()) {
        video.checkKeys({"size"});
        const JsonValue size = video["size"];
        if (size.exists()) {
            if (!size.isArray() || size.size() != 2) {
                size.problem("expected [width, height] in pixels");
            } else {
                const auto w = size.at(0).integer(16, 8192), h = size.at(1).integer(16, 8192);
                if (w && h && (*w % 2 || *h % 2))
                    size.problem("expected even width and height (H.264 in yuv420p), got " + std::to_string(*w) + "x" +
                                 std::to_string(*h));
                if (w && h) {
                    m.videoWidth = *w;
                    m.videoHeight = *h;
                }
            }
        }
    }
    // The manifest may place its library inside its own folder only: a shared manifest must not write
    // into the reader's home. A library elsewhere is named on the command line (--library DIR).
    m.outputRoot = base / "library";
    if (auto s = root["outputRoot"].string(); s && !s->empty()) {
        const fs::path named(*s);
        if (!staysBelow(named) || hasControlCharacter(*s))
            root["outputRoot"].problem("expected a folder inside the manifest's folder, got \"" + shownName(*s) +
                                       "\"; put a library anywhere else with 'batch --library DIR'");
        else
            m.outputRoot = (base / named).lexically_normal();
    }
    if (auto s = root["output"].string()) {
        if (s->empty() || fs::path(*s).is_absolute() || s->find("..") != std::string::npos || hasControlCharacter(*s))
            root["output"].problem("expected a relative path pattern inside outputRoot, such as \"{scene}/{preset}/{clip}-{format}\"");
        else
            m.output = *s;
    }
    if (const JsonValue r = root["resources"]; r.expectObject()) {
        r.checkKeys({"cpusPerTask", "memoryMB", "minutes", "partition"});
        if (auto x = r["cpusPerTask"].integer(1, 256)) m.resources.cpusPerTask = *x;
        if (auto x = r["memoryMB"].integer(64, 1048576)) m.resources.memoryMB = *x;
        if (auto x = r["minutes"].integer(1, 10080)) m.resources.minutes = *x;
        if (auto x = r["partition"].string()) {
            if (x->find_first_of(" \t\n'\"$`\\;") != std::string::npos || hasControlCharacter(*x))
                r["partition"].problem("expected a partition name (no spaces or shell characters)");
            else
                m.resources.partition = *x;
        }
    }
    if (!issues.empty())
        return std::nullopt;
    return m;
}

}  // namespace

Result<BatchManifest> loadBatchManifest(const fs::path& path) {
    JsonIssues issues(path.string());
    auto manifest = readBatchManifest(path, issues);
    if (!manifest)
        return Status::error(issues.summary());
    return std::move(*manifest);
}

std::vector<std::string> validateBatchManifest(const fs::path& path, std::size_t* jobs) {
    JsonIssues issues(path.string());
    const auto manifest = readBatchManifest(path, issues);
    if (!manifest)
        return issues.messages();
    auto planned = planBatch(*manifest);
    if (!planned)
        return {planned.message()};
    if (jobs)
        *jobs = planned->size();
    return {};
}

Result<std::vector<BatchJob>> planBatch(const BatchManifest& manifest, const BatchPlanProgress& progress) {
    std::vector<BatchJob> jobs;
    std::map<fs::path, std::string> writers;  // output -> job id, to refuse collisions
    std::set<std::string> ids;
    const std::vector<fs::path> presets = manifest.presets.empty() ? std::vector<fs::path>{fs::path()} : manifest.presets;
    // The product's size before anything is expanded (a scene's default clip counts one).
    const double product = double(manifest.scenes.size()) * double(presets.size()) *
                           double(std::max<std::size_t>(manifest.clips.size(), 1)) * double(manifest.formats.size());
    if (product > kMaxBatchJobs)
        return Status::error(manifest.path.string() + ": the manifest expands to " + std::to_string(std::llround(product)) +
                             " jobs (scenes x presets x clips x formats), more than the " +
                             std::to_string(std::llround(kMaxBatchJobs)) + " a library may hold: split it into several manifests");
    const auto total = std::size_t(product);
    // Every input is read once: a large product names the same few files in every job.
    std::map<fs::path, std::uint64_t> contentHashes;
    auto contentHash = [&](const fs::path& input) -> Result<std::uint64_t> {
        if (auto it = contentHashes.find(input); it != contentHashes.end())
            return it->second;
        ContentHash hash;
        if (Status s = hashFile(input, hash); !s)
            return s;
        contentHashes.emplace(input, hash.value);
        return hash.value;
    };
    for (const fs::path& preset : presets)
        if (!preset.empty())
            if (auto p = loadMaterialPreset(preset); !p)
                return Status::error(manifest.path.string() + ": /presets: " + p.message());
    const fs::path root = manifest.outputRoot.lexically_normal();
    for (const fs::path& scene : manifest.scenes) {
        auto project = loadProject(scene);
        if (!project)
            return Status::error(manifest.path.string() + ": /scenes: " + project.message());
        std::vector<fs::path> sceneInputs = {scene};
        for (const std::string& mesh : project->meshReferences)
            sceneInputs.push_back((scene.parent_path() / mesh).lexically_normal());
        std::vector<std::string> clips = manifest.clips;
        if (clips.empty())
            clips.push_back(project->clips.defaultClip);  // empty: the drivers from frame 0
        for (const std::string& clip : clips) {
            if (!clip.empty() && !project->clips.findClip(clip))
                return Status::error(manifest.path.string() + ": /clips: scene '" + scene.string() + "' has no clip \"" +
                                     clip + "\"");
            // A scene's own default clip is named by the scene, not the manifest: it must give a name too.
            if (!clip.empty() && libraryName(clip).find_first_not_of('.') == std::string::npos)
                return Status::error(manifest.path.string() + ": scene '" + scene.string() + "': its clip \"" +
                                     shownName(clip) + "\" gives no name for the library's outputs: rename the clip");
        }
        for (const fs::path& preset : presets)
            for (const std::string& clip : clips)
                for (const std::string& format : manifest.formats) {
                    BatchJob job;
                    job.scene = scene;
                    job.preset = preset;
                    job.clip = clip;
                    job.format = format;
                    job.frames = manifest.frames;
                    const ExportFormat* exportFormat = findExportFormat(format);
                    job.compress = manifest.compress && exportFormat && exportFormat->takesCompress;
                    if (isVideoFormat(format)) {
                        job.videoWidth = manifest.videoWidth;
                        job.videoHeight = manifest.videoHeight;
                    }
                    const std::string sceneName = libraryName(scene.stem().string());
                    const std::string presetName = preset.empty() ? "as-authored" : libraryName(preset.stem().string());
                    const std::string clipName = clip.empty() ? "drivers" : libraryName(clip);
                    job.id = slug(sceneName) + "." + slug(presetName) + "." + slug(clipName) + "." + format;
                    std::string rel = manifest.output;
                    for (const auto& [key, value] : {std::pair<std::string, std::string>{"{scene}", sceneName},
                                                     {"{preset}", presetName},
                                                     {"{clip}", clipName},
                                                     {"{format}", format}})
                        for (std::size_t at = 0; (at = rel.find(key, at)) != std::string::npos; at += value.size())
                            rel.replace(at, key.size(), value);
                    job.output = (root / (rel + extensionOf(format))).lexically_normal();
                    // What the names above cannot do, checked once more where it matters: the output lies
                    // inside the library.
                    if (!liesInside(job.output, root))
                        return Status::error(manifest.path.string() + ": /output: job " + job.id + " would write '" +
                                             job.output.string() + "', outside the library " + root.string());
                    if (!ids.insert(job.id).second)
                        return Status::error(manifest.path.string() + ": two jobs have the id " + job.id +
                                             " (scenes or presets of the same file name in different folders)");
                    if (auto [it, fresh] = writers.emplace(job.output, job.id); !fresh)
                        return Status::error(manifest.path.string() + ": /output: jobs " + it->second + " and " + job.id +
                                             " would both write '" + job.output.string() +
                                             "'; the pattern needs each of {scene}, {preset}, {clip} and {format} that varies");
                    job.inputs = sceneInputs;
                    if (!preset.empty())
                        job.inputs.push_back(preset);
                    ContentHash hash;
                    hash.add(std::string("softtouch-batch-job 2 " SOFTTOUCH_VERSION));
                    for (const std::string& field : {job.format, job.clip, std::to_string(job.frames),
                                                     std::to_string(job.videoWidth), std::to_string(job.videoHeight)})
                        hash.add(field);
                    if (job.compress)
                        hash.add(std::string("compress"));
                    for (const fs::path& input : job.inputs) {
                        auto content = contentHash(input);
                        if (!content)
                            return Status::error(manifest.path.string() + ": job " + job.id + ": " + content.message());
                        hash.add(&content.value(), sizeof(std::uint64_t));
                    }
                    job.hash = hash.value;
                    jobs.push_back(std::move(job));
                    if (progress && jobs.size() % 1024 == 0)
                        progress(jobs.size(), std::max(total, jobs.size()));
                }
    }
    if (progress)
        progress(jobs.size(), jobs.size());
    return jobs;
}

fs::path batchStampPath(const BatchManifest& manifest, const BatchJob& job) {
    return manifest.outputRoot / ".softtouch-batch" / (job.id + ".json");
}

std::optional<std::vector<fs::path>> batchStampFiles(const BatchManifest& manifest, const BatchJob& job) {
    const fs::path stamp = batchStampPath(manifest, job);
    std::error_code ec;
    if (!fs::is_regular_file(stamp, ec))
        return std::nullopt;
    std::ifstream in(stamp, std::ios::binary);
    const nlohmann::json doc = nlohmann::json::parse(in, nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || doc.value("format", "") != kStampFormat ||
        doc.value("hash", "") != hashText(job.hash) || !doc.contains("files") || !doc["files"].is_array())
        return std::nullopt;
    std::vector<fs::path> files;
    for (const auto& f : doc["files"]) {
        if (!f.is_object() || !f.contains("path") || !f["path"].is_string() || !f.contains("bytes") ||
            !f["bytes"].is_number_unsigned())
            return std::nullopt;
        // A stamp names files inside the library only; one edited to point elsewhere is not a stamp.
        const fs::path relative(f["path"].get<std::string>());
        if (relative.empty() || !staysBelow(relative))
            return std::nullopt;
        const fs::path file = manifest.outputRoot / relative;
        if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) != f["bytes"].get<std::uintmax_t>())
            return std::nullopt;
        files.push_back(file);
    }
    return files;
}

bool batchJobUpToDate(const BatchManifest& manifest, const BatchJob& job) {
    return batchStampFiles(manifest, job).has_value();
}

Status writeBatchStamp(const BatchManifest& manifest, const BatchJob& job, const std::vector<fs::path>& files) {
    nlohmann::json doc;
    doc["format"] = kStampFormat;
    doc["id"] = job.id;
    doc["hash"] = hashText(job.hash);
    doc["files"] = nlohmann::json::array();
    for (const fs::path& file : files) {
        std::error_code ec;
        const auto bytes = fs::file_size(file, ec);
        if (ec)
            return Status::error("job " + job.id + ": cannot stamp '" + file.string() + "': " + ec.message());
        doc["files"].push_back({{"path", file.lexically_relative(manifest.outputRoot).generic_string()}, {"bytes", bytes}});
    }
    const fs::path stamp = batchStampPath(manifest, job);
    std::error_code ec;
    fs::create_directories(stamp.parent_path(), ec);
    if (ec)
        return Status::error("cannot create '" + stamp.parent_path().string() + "': " + ec.message());
    removeStaleTemporaries(stamp);  // a stamp half-written when its job was killed
    return writeFileAtomically(stamp, doc.dump(1) + "\n");
}

}  // namespace softtouch::io
