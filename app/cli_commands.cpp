#include "app/bundled_paths.h"
#include "app/cli_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"
#include "core/base/ranges.h"

#include "io/documents/project_file.h"
#include "io/export/export_formats.h"
#include "io/files/atomic_file.h"
#include "io/import/animation_import.h"
#include "io/import/mesh_import.h"
#include "io/pipeline/bake.h"
#include "io/pipeline/batch_plan.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

namespace softtouch::cli {
namespace {

/// What bake does, and its formats with their extensions from the export registry (io/export/export_formats.h).
std::string bakeAbout() {
    std::string text = R"(Bake a clip of SCENE (--clip NAME; without it the scene's default clip, or when it has none its
drivers simulated from rest, frame i at i/fps s) into a vertex cache.
The rest mesh the cache matches is written beside it as FILE with extension .obj (for an OBJ
sequence, FILE itself; frames go to NAME_0000.obj, NAME_0001.obj, ...).

Formats (docs/formats.md):
)";
    for (const io::ExportFormat& f : io::exportFormats())
        text += helpEntry(f.name, f.help);
    return text;
}

}  // namespace

int runBake(const std::vector<std::string>& args) {
    std::string scenePath, outPath, clipName;
    const io::ExportFormat* format = nullptr;
    std::optional<double> frames, fps, threads, error, targets, bones;
    std::vector<std::string> objects;
    bool quiet = false, eachObject = false, groups = false, compress = false;
    std::optional<io::ClipExportOptions::SkinRig> rig;
    CommandLine line("bake", bakeAbout());
    line.positional("SCENE", scenePath, "The project to simulate (*.softtouch).");
    line.text("--out", outPath, {"FILE", "Output. Format from the extension: " + io::exportExtensions() + ".", true});
    line.value("--format", [&format](const std::string& name) {
        format = io::findExportFormat(name);
        return format ? std::string() : "expects " + io::exportFormatNames() + ", got '" + name + "'";
    }, {io::exportFormatNames("|", "|"), "The format, instead of the one the extension names."});
    line.text("--clip", clipName, {"NAME", "A clip of the scene's clip library (its frames, fps, loop closure)."});
    line.number("--frames", frames, ranges::kFrames,
                {"N", "Frames to write (default: the clip's or the scene's length; a loop clip cycles)."});
    line.number("--fps", fps, ranges::kFps, {"F", "Frames per second (default: the scene's clip rate; a clip keeps its own)."});
    // The export's own ranges (they depend on the format) are io::exportOptions' to check.
    line.number("--error", error, NumberRange{},
                {"E", "pca: each frame's RMS vertex error, skin: the clip's RMS vertex error, at most E times the rest "
                      "mesh's bounding-box diagonal (0 < E <= 0.1; default 0.005)."});
    line.number("--targets", targets, NumberRange{}, {"K", "pca: at most K morph targets, the mean included (2..256, default 33)."});
    line.number("--bones", bones, NumberRange{}, {"K", "skin: exactly K bones (1..256) instead of the fewest within --error; on the source rig, K helper "
                      "bones."});
    line.value("--rig", [&rig](const std::string& name) {
        rig = io::skinRigNamed(name);
        return rig ? std::string() : "expects auto, source or fitted, got '" + name + "'";
    }, {"auto|source|fitted", "skin: the bones. source keeps the skeleton the object's mesh file skinned it to (its "
                             "joints, hierarchy, bind pose and animation) and adds at most --bones helper bones "
                             "(default 16) for the wobble; fitted fits rigid bones to the clip alone; auto (the "
                             "default) takes source where the one object baked came with a skinned base animation."});
    line.flag("--compress", compress,
              "glb, pca, skin (a .glb path): pack the file for shipping with EXT_meshopt_compression (three.js, "
              "Babylon.js, Unity glTFast read it; assimp, Blender, Godot do not): positions stay bit-exact, normals "
              "become 16-bit octahedral vectors, morph targets keep 16-bit mantissas, skin weights 8 bits. Prints the "
              "size against PC2.");
    line.texts("--object", objects,
               {"NAME", "Only this object's mesh in the cache (again for more; the scene is still simulated whole)."});
    line.flag("--each-object", eachObject,
              "One cache per object: FILE's name + \"-OBJECT\" (swim.pc2 -> swim-angelfish.pc2, ...).");
    line.flag("--groups", groups,
              "OBJ files (the rest mesh, an OBJ sequence's frames) name each object's faces with a \"g OBJECT\" line, "
              "so a DCC imports one part per object.");
    line.number("--threads", threads, {0, 1024, true}, {"N", "Deformation threads (default: all)."});
    line.flag("--quiet", quiet, "No progress output.");
    if (const auto exit = line.parse(args))
        return *exit;
    if (!format)
        format = io::exportFormatForPath(outPath);
    if (!format)
        return line.usage("cannot tell the format from '" + outPath + "'; use " + io::exportExtensions() + " or --format");
    if (eachObject && !objects.empty())
        return line.usage("--each-object bakes every object to its own cache; it takes no --object");
    auto exportOptions = io::exportOptions(*format, {error, targets, bones, compress, rig});
    if (!exportOptions)
        return line.usage(exportOptions.message());
    io::BakeOptions options;
    options.output = outPath;
    options.format = format;
    options.exportOptions = exportOptions.value();
    options.frames = frames ? int(*frames) : 0;
    options.fps = fps.value_or(0.0);
    options.threads = threads ? int(*threads) : 0;
    options.objects = objects;
    options.objectGroups = groups;
    if (!quiet) {
        // A tenth of a second apart at most: a frame that takes long (a fine step, a big mesh) still shows, and
        // a program reading the pipe (the Blender add-on's progress bar) sees the bake move.
        auto shown = std::make_shared<std::chrono::steady_clock::time_point>();
        const auto due = [shown] {
            const auto now = std::chrono::steady_clock::now();
            if (now - *shown < std::chrono::milliseconds(100))
                return false;
            *shown = now;
            return true;
        };
        // A clip of the library is simulated whole first, then written.
        options.simulating = [due](double done) {
            if (due())
                std::fprintf(stderr, "\rsimulating clip %d%%", int(100.0 * done));
            return true;
        };
        options.progress = [due](int done, int total) {
            if (done == total || due())
                std::fprintf(stderr, "\rbaking frame %d/%d", done, total);
            if (done == total)
                std::fputc('\n', stderr);
            return true;
        };
    }

    auto project = io::loadProjectToRun(scenePath);
    if (!project)
        return fail(project.message());
    options.clips = &project->clips;
    options.clip = clipName;
    options.meshSources = io::meshSources(project.value());
    std::filesystem::path madeFolder;
    if (const std::string problem = makeOutputFolders(outPath, madeFolder); !problem.empty())
        return fail(problem);
    // A failed bake takes away the folders it made for its output.
    const auto failed = [&](const std::string& message) {
        removeEmptyFolders(madeFolder);
        return fail(message);
    };
    if (eachObject) {
        auto results = io::bakeEachObject(project->scene, options);
        if (!results)
            return failed(results.message());
        for (const io::BakeResult& r : results.value())
            std::printf("wrote %s (%s, %d frames, %zu points), rest mesh %s\n", r.cache.string().c_str(),
                        std::string(format->name).c_str(), r.frames, r.points, r.restMesh.string().c_str());
        return 0;
    }
    auto result = io::bake(project->scene, options);
    if (!result)
        return failed(result.message());
    const std::size_t shown = std::min<std::size_t>(result->warnings.size(), 5);
    for (std::size_t i = 0; i < shown; ++i)
        std::fprintf(stderr, "softtouch-cli: warning: %s\n", result->warnings[i].c_str());
    if (result->warnings.size() > shown)
        std::fprintf(stderr, "softtouch-cli: warning: ... and %zu more\n", result->warnings.size() - shown);
    std::printf("wrote %s (%s, %d frames, %zu points)\n", result->cache.string().c_str(),
                std::string(format->name).c_str(), result->frames, result->points);
    printWritten(std::span(result->files).subspan(1));
    std::printf("rest mesh %s\n", result->restMesh.string().c_str());
    for (const std::string& note : result->notes)
        std::printf("%s\n", note.c_str());
    for (const std::string& note : project->importNotes)  // what each animated import found (take, unit)
        std::printf("base animation of %s\n", note.c_str());
    if (const int unchanged = result->frames * result->objects - result->meshEvaluations; unchanged > 0)
        std::printf("%d of %d object frames unchanged (asleep or held): their meshes were not deformed again\n",
                    unchanged, result->frames * result->objects);
    if (!result->clip.empty())
        std::printf("clip %s\n", result->clip.c_str());
    if (result->seam)
        std::printf("loop seam: jump %.6g m = %.3f x the median frame-to-frame motion (%.6g m), %.3f x the steps "
                    "beside the seam, on the lattice nodes\n",
                    result->seam->jump, result->seam->ratio, result->seam->medianStep, result->seam->localRatio);
    return 0;
}

namespace {

/// Whether validate reads `file` as one of SoftTouch's JSON documents (a project, preset or trajectory); anything
/// else is a mesh file for assimp.
bool isSoftTouchDocument(const std::filesystem::path& file) {
    const std::string extension = file.extension().string();
    for (const char* document : {".softtouch", ".stpreset", ".sttraj", ".json"})
        if (extension == document)
            return true;
    return false;
}

/// A mesh file as the editor and a project's "mesh" would import it: its size, and its takes (what a project's
/// animation.take names). Empty on success; otherwise the problem, naming the file.
std::string describeMeshFile(const std::string& file, std::string& summary) {
    auto mesh = io::importMesh(file);
    if (!mesh)
        return mesh.message();
    summary = file + ": ok, a mesh of " + std::to_string(mesh->positions.size()) + " vertices and " +
              std::to_string(mesh->triangles.size()) + " triangles; ";
    auto takes = io::animationTakes(file);
    if (!takes) {
        summary += "no animation";
        return {};
    }
    summary += std::to_string(takes->size()) + (takes->size() == 1 ? " take:" : " takes:");
    for (const auto& [name, seconds] : takes.value()) {
        char length[32];
        std::snprintf(length, sizeof length, "%g", seconds);
        summary += " \"" + name + "\" (" + length + " s)";
    }
    return {};
}

}  // namespace

int runValidate(const std::vector<std::string>& args) {
    std::vector<std::string> files;
    CommandLine line("validate", R"(Check *.softtouch projects, *.stpreset presets, *.sttraj device trajectories (the
referenced meshes and presets too) and *.stbatch batch manifests (planned as batch would) and print every
problem found, one per line, each naming the file, the JSON pointer and what was expected. Any other FILE
is read as a mesh (OBJ, FBX, glTF/GLB, PLY, STL, DAE, ...): its vertices and triangles and the takes of its
animation, the names a project's animation.take uses.
)",
                     "Exit status 0 when every file is valid, 1 otherwise, 2 on bad usage (put -- before a file whose\n"
                     "name starts with '-').");
    line.positionals("FILE", files, "");
    line.setUnknownOptionNote(" (validate takes files; write ./NAME or put -- before a file whose name starts with '-')");
    if (const auto exit = line.parse(args))
        return *exit;
    int bad = 0;
    for (const std::string& file : files) {
        if (std::filesystem::path(file).extension() == ".stbatch") {  // a batch manifest, planned as batch would
            std::size_t jobs = 0;
            const std::vector<std::string> problems = io::validateBatchManifest(file, &jobs);
            for (const std::string& p : problems)
                std::fprintf(stderr, "%s\n", p.c_str());
            if (problems.empty())
                std::printf("%s: ok, %zu jobs\n", file.c_str(), jobs);
            else
                ++bad;
            continue;
        }
        if (!isSoftTouchDocument(file)) {
            std::string summary;
            if (const std::string problem = describeMeshFile(file, summary); !problem.empty()) {
                std::fprintf(stderr, "%s\n", problem.c_str());
                ++bad;
            } else {
                std::printf("%s\n", summary.c_str());
            }
            continue;
        }
        const std::vector<std::string> problems = io::validateFile(file);
        for (const std::string& p : problems)
            std::fprintf(stderr, "%s\n", p.c_str());
        if (problems.empty())
            std::printf("%s: ok\n", file.c_str());
        else
            ++bad;
    }
    return bad == 0 ? 0 : 1;
}

}  // namespace softtouch::cli
