#include "app/cli_commands.h"
#include "app/bundled_paths.h"
#include "app/cli_offscreen_gui.h"
#include "app/cli_support.h"
#include "core/ranges.h"

#include "bench/study_plot.h"
#include "bench/bench.h"
#include "bench/study.h"
#include "io/atomic_file.h"
#include "io/bake.h"
#include "io/project_file.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>

namespace softtouch::cli {
namespace {

constexpr const char* kBakeUsage = R"(Usage: softtouch-cli bake SCENE --out FILE [options]

Bake a clip of SCENE (--clip NAME; without it the scene's default clip, or when it has none its
drivers simulated from rest, frame i at i/fps s) into a vertex cache.
The rest mesh the cache matches is written beside it as FILE with extension .obj (for an OBJ
sequence, FILE itself; frames go to NAME_0000.obj, NAME_0001.obj, ...).

Formats (docs/formats.md):
  pc2, mdd          vertex caches
  objseq            one OBJ per frame
  gltf, glb         glTF 2.0 morph targets (one per frame) and a weights animation
  pca               glTF/GLB (by the extension, default .glb) with compressed morphs: the frames'
                    mean plus the fewest principal components that keep every frame's RMS vertex
                    error within --error; prints the targets, the errors and the size against PC2
  skin              glTF/GLB (by the extension, default .glb) as linear blend skinning: rigid bones
                    fitted to the clip (Le & Deng 2012), at most 4 weights a vertex, a bone animation;
                    the fewest of 8/16/32/64 bones within --error, or --bones K; prints the errors
  vat               FILE is a base path: FILE.vat-position.exr, FILE.vat-normal.exr (half float),
                    FILE.vat-mesh.glb, FILE.vat.json
  lattice           FILE is a base path: FILE.lattice.glb (mesh with lattice u,v,w),
                    FILE.lattice.bin (node positions per frame); shaders in io/shaders/

Options:
  --out FILE        Output (required). Format from the extension: .pc2, .mdd, .obj (sequence),
                    .gltf, .glb.
  --format NAME     pc2 | mdd | objseq | gltf | glb | vat | lattice (overrides the extension).
  --clip NAME       A clip of the scene's clip library (its frames, fps, loop closure).
  --frames N        Frames to write (default: the clip's or the scene's length; a loop clip cycles).
  --fps F           Frames per second (default: the scene's clip rate; a clip keeps its own).
  --threads N       Deformation threads (default: all).
  --error E         pca: each frame's RMS vertex error, skin: the clip's RMS vertex error, at most E
                    times the rest mesh's bounding-box diagonal (0 < E <= 0.1; default 0.005).
  --bones K         skin: exactly K bones (1..256) instead of the fewest within --error.
  --targets K       pca: at most K morph targets, the mean included (2..256, default 33).
  --quiet           No progress output.
)";


}  // namespace

int runBake(const std::vector<std::string>& args) {
    const auto usage = [](const std::string& message) { return usageError(message, "bake"); };
    std::string scenePath, outPath, formatName, clipName;
    std::optional<double> frames, fps, threads, error, targets, bones;
    bool quiet = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&](const char* name) -> std::optional<std::string> {
            if (i + 1 >= args.size())
                return std::nullopt;
            (void)name;
            return args[++i];
        };
        if (a == "--help" || a == "-h") {
            std::fputs(kBakeUsage, stdout);
            return 0;
        }
        if (a == "--quiet") {
            quiet = true;
        } else if (a == "--out" || a == "--format" || a == "--frames" || a == "--fps" || a == "--threads" ||
                   a == "--clip" || a == "--error" || a == "--targets" || a == "--bones") {
            const auto v = value(a.c_str());
            if (!v)
                return usage(a + " needs a value");
            if (a == "--out") {
                outPath = *v;
            } else if (a == "--format") {
                formatName = *v;
            } else if (a == "--clip") {
                clipName = *v;
            } else {
                const auto n = parseNumber(*v);
                if (!n)
                    return usage(a + " expects a number, got '" + *v + "'");
                (a == "--frames"        ? frames
                 : a == "--fps"         ? fps
                 : a == "--threads"     ? threads
                 : a == "--error"       ? error
                 : a == "--targets"     ? targets
                                        : bones) = *n;
            }
        } else if (!a.empty() && a[0] == '-') {
            return usage("unknown option '" + a + "'");
        } else if (scenePath.empty()) {
            scenePath = a;
        } else {
            return usage("unexpected argument '" + a + "'");
        }
    }
    if (scenePath.empty())
        return usage("bake needs a SCENE file");
    if (outPath.empty())
        return usage("bake needs --out FILE");
    io::BakeOptions options;
    options.output = outPath;
    const bool pca = formatName == "pca", skin = formatName == "skin";
    if (pca || skin)  // compressed morphs or bones: glTF exports with their own options, .gltf or .glb by the extension
        formatName = io::cacheFormatFromPath(outPath) == io::CacheFormat::Gltf ? "gltf" : "glb";
    if (!formatName.empty()) {
        const auto f = io::parseCacheFormat(formatName);
        if (!f)
            return usage("unknown format '" + formatName + "' (expected pc2, mdd, objseq, gltf, glb, pca, skin, vat or lattice)");
        options.format = *f;
    } else {
        const auto f = io::cacheFormatFromPath(outPath);
        if (!f)
            return usage("cannot tell the format from '" + outPath + "'; use .pc2, .mdd, .obj, .gltf, .glb or --format");
        options.format = *f;
    }
    if (frames && (*frames < 1 || *frames > ranges::kMaxFrames || std::floor(*frames) != *frames))
        return usage("--frames must be a whole number in [1, 1000000], got " + formatValue(*frames));
    if (fps && (*fps < ranges::kMinFps || *fps > ranges::kMaxFps))
        return usage("--fps must be in [1, 1000], got " + formatValue(*fps));
    if (threads && (*threads < 0 || *threads > 1024 || std::floor(*threads) != *threads))
        return usage("--threads must be a whole number in [0, 1024]");
    if (error && !pca && !skin)
        return usage("--error is for --format pca and --format skin");
    if (targets && !pca)
        return usage("--targets is for --format pca");
    if (bones && !skin)
        return usage("--bones is for --format skin");
    if (bones && error)
        return usage("--bones fixes the bone count; --error chooses it: give one");
    if (bones && (*bones < 1 || *bones > 256 || std::floor(*bones) != *bones))
        return usage("--bones must be a whole number in [1, 256], got " + formatValue(*bones));
    if (error && !(*error > 0 && *error <= 0.1))
        return usage("--error must be in (0, 0.1] (a fraction of the diagonal), got " + formatValue(*error));
    if (targets && (*targets < 2 || *targets > 256 || std::floor(*targets) != *targets))
        return usage("--targets must be a whole number in [2, 256] (the mean and at least one component), got " +
                     formatValue(*targets));
    if (pca) {
        options.exportOptions.gltfMorphError = error.value_or(io::ClipExportOptions::kDefaultCompressionError);
        options.exportOptions.gltfMaxMorphs = targets ? int(*targets) - 1 : 32;
    }
    if (skin) {
        options.exportOptions.skinBones = bones ? int(*bones) : 0;
        options.exportOptions.skinError = bones ? 0.0 : error.value_or(io::ClipExportOptions::kDefaultCompressionError);
    }
    options.frames = frames ? int(*frames) : 0;
    options.fps = fps.value_or(0.0);
    options.threads = threads ? int(*threads) : 0;
    if (!quiet) {
        options.progress = [](int done, int total) {
            if (done == total || done % 24 == 0)
                std::fprintf(stderr, "\rbaking frame %d/%d", done, total);
            if (done == total)
                std::fputc('\n', stderr);
            return true;
        };
    }

    auto project = io::loadProject(scenePath);
    if (!project)
        return fail(project.message());
    options.clips = &project->clips;
    options.clip = clipName;
    auto result = io::bake(project->scene, options);
    if (!result)
        return fail(result.message());
    const std::size_t shown = std::min<std::size_t>(result->warnings.size(), 5);
    for (std::size_t i = 0; i < shown; ++i)
        std::fprintf(stderr, "softtouch-cli: warning: %s\n", result->warnings[i].c_str());
    if (result->warnings.size() > shown)
        std::fprintf(stderr, "softtouch-cli: warning: ... and %zu more\n", result->warnings.size() - shown);
    std::printf("wrote %s (%s, %d frames, %zu points)\n", result->cache.string().c_str(),
                std::string(io::cacheFormatName(options.format)).c_str(), result->frames, result->points);
    for (std::size_t i = 1; i < result->files.size(); ++i)
        std::printf("wrote %s\n", result->files[i].string().c_str());
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

int runValidate(const std::vector<std::string>& args) {
    const auto usage = [](const std::string& message) { return usageError(message, "validate"); };
    if (args.empty())
        return usage("validate needs at least one FILE");
    if (args.front() == "--help" || args.front() == "-h") {
        std::puts("Usage: softtouch-cli validate FILE...\n\nCheck *.softtouch projects, *.stpreset presets and *.sttraj device trajectories (the "
                  "referenced meshes and presets too) and print every problem found, one per line.");
        return 0;
    }
    for (const std::string& file : args)
        if (file.size() > 1 && file[0] == '-')
            return usage("unknown option '" + file + "' (validate takes files; write ./" + file + " for a file of that name)");
    int bad = 0;
    for (const std::string& file : args) {
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

int runBench(const std::vector<std::string>& args) {
    const auto usage = [](const std::string& message) { return usageError(message, "bench"); };
    bench::BenchOptions options;
    std::string jsonPath;
    std::filesystem::path hapticScene;
    for (std::size_t i = 0; i < args.size(); ++i) {
        if (args[i] == "--help" || args[i] == "-h") {
            std::puts("Usage: softtouch-cli bench [--json FILE] [--quick] [--only KEY] [--haptic-scene FILE]\n\n"
                      "Lattice step cost per integrator, deformation throughput against a plain scalar kernel,\n"
                      "the paper's Table 1 redone (lattice vs global and local mass-spring vs Bullet btSoftBody),\n"
                      "and the cost of unused features. Every figure comes with its baseline from the same run.\n"
                      "  --json FILE   also write the results as JSON (keys: docs/benchmarks.md)\n"
                      "  --quick       small sizes only (seconds, not minutes)\n"
                      "  --only KEY    one section: lattice_step_us, lattice_step_us_8x4x4, features, deform, table1, haptic\n"
                      "  --haptic-scene FILE  scene whose first object the haptic loop runs on, besides a generated\n"
                      "                1,000,000-triangle one (default presets/scenes/star-drag.softtouch)\n"
                      "  --haptic-priority N  SCHED_FIFO priority the haptic loop asks for (default 80; 0: normal)");
            return 0;
        }
        if (args[i] == "--quick")
            options.quick = true;
        else if (args[i] == "--only" && i + 1 < args.size())
            options.only = args[++i];
        else if (args[i] == "--haptic-priority" && i + 1 < args.size()) {
            const std::string& v = args[++i];
            int priority = -1;
            const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), priority);
            if (ec != std::errc() || end != v.data() + v.size() || priority < 0 || priority > 99)
                return usage("--haptic-priority expects an integer in [0, 99], got '" + v + "'");
            options.hapticPriority = priority;
        } else if (args[i] == "--haptic-scene" && i + 1 < args.size())
            hapticScene = args[++i];
        else if (args[i] == "--json" && i + 1 < args.size())
            jsonPath = args[++i];
        else
            return usage("unknown bench argument '" + args[i] + "'");
    }
    static const std::set<std::string> sections = {"lattice_step_us", "lattice_step_us_8x4x4", "features",
                                                   "deform", "table1", "haptic"};
    if (!options.only.empty() && !sections.count(options.only))
        return usage("unknown bench section '" + options.only + "'");
    std::optional<io::Project> star;
    if (options.only.empty() || options.only == "haptic") {
        // The star scene from the working directory (the repository root), else the bundled one.
        if (hapticScene.empty()) {
            hapticScene = "presets/scenes/star-drag.softtouch";
            if (!std::filesystem::exists(hapticScene))
                hapticScene = app::bundledFolder("presets", "presets") / "scenes/star-drag.softtouch";
        }
        auto project = io::loadProject(hapticScene);
        if (!project)
            return fail(project.message());
        star = std::move(project.value());
        options.hapticScenes.push_back({hapticScene.stem().string(), &star->scene, Vec3(0.95, 0.95, 0.5)});
    }
    const nlohmann::json result = bench::runBench(options, std::cout);
    if (!jsonPath.empty()) {
        if (Status s = io::writeFileAtomically(jsonPath, result.dump(2) + "\n"); !s)
            return fail(s.message());
        std::printf("\nwrote %s\n", jsonPath.c_str());
    }
    return 0;
}

int runStudy(const std::vector<std::string>& args) {
    const auto usage = [](const std::string& message) { return usageError(message, "study"); };
    std::string scenePath, outDir, applyPath;
    std::optional<double> target;
    bench::StudyOptions options;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--help" || a == "-h") {
            std::puts("Usage: softtouch-cli study SCENE [--out DIR] [--quick] [--error KIND] [--repeats N]\n"
                      "                           [--target ERROR [--apply OUT.softtouch]]\n\n"
                      "For every integrator x dt (1/1000 .. 1/24 s) x lattice (2^3, 3^3, 4^3, 6^3, 8^3 Bezier; 6^3, 8^3\n"
                      "B-spline), on the scene's first object over the scene's clip (world frames / fps, as bake runs it):\n"
                      "cost per simulated second (median of repeats), integration error (against the same lattice\n"
                      "converged in time), model error (that converged run against the 8x8x8 Bezier converged) and the\n"
                      "total error (against the reference), RMS relative to the box diagonal; energy drift, amplitude\n"
                      "lost per period and frequency error in free vibration.\n"
                      "  --out DIR       write DIR/study.csv, DIR/study.md and DIR/study.png (error against cost, Pareto front)\n"
                      "  --quick         fewer steps and lattices (3 x 3), the same clip\n"
                      "  --error KIND    the error the Pareto front and --target use: total (default), integration, model\n"
                      "  --repeats N     timed runs per setting, cost is their median (default 5)\n"
                      "  --lattices L    the lattices instead of the grid's: e.g. bezier2,bezier4,bspline10 (n^3 nodes)\n"
                      "  --integrators I the integrators instead of all four: e.g. verlet,xpbd\n"
                      "  --steps S       the steps per second instead of the grid's: e.g. 24,240\n"
                      "  --target ERROR  print the cheapest setting whose error is at most ERROR (e.g. 0.005)\n"
                      "  --apply OUT     write SCENE with that setting (integrator, dt; the first object moved to its\n"
                      "                  lattice, material carried over) to OUT, read it back and re-measure it as written");
            return 0;
        }
        if (a == "--quick") {
            options.quick = true;
        } else if ((a == "--out" || a == "--target" || a == "--apply" || a == "--error" || a == "--repeats" ||
                    a == "--lattices" || a == "--integrators" || a == "--steps") &&
                   i + 1 < args.size()) {
            const std::string v = args[++i];
            std::vector<std::string> items;
            for (std::size_t start = 0; start <= v.size();) {
                const std::size_t comma = std::min(v.find(',', start), v.size());
                items.push_back(v.substr(start, comma - start));
                start = comma + 1;
            }
            if (a == "--lattices") {
                for (const std::string& item : items) {
                    const bool bezier = item.rfind("bezier", 0) == 0, bspline = item.rfind("bspline", 0) == 0;
                    const auto n = bezier || bspline ? parseNumber(item.substr(bezier ? 6 : 7)) : std::nullopt;
                    const LatticeShape shape{bezier ? LatticeKind::Bezier : LatticeKind::BSpline, {int(n.value_or(0)), int(n.value_or(0)), int(n.value_or(0))}};
                    if (!n || *n != std::floor(*n) || !shape.validate())
                        return usage("--lattices expects bezierN or bsplineN (N nodes per axis) separated by commas, got '" + item + "'");
                    options.lattices.push_back(shape);
                }
            } else if (a == "--integrators") {
                for (const std::string& item : items) {
                    const auto kind = parseIntegratorKind(item);
                    if (!kind)
                        return usage("--integrators expects integrator names separated by commas, got '" + item + "'");
                    options.integrators.push_back(*kind);
                }
            } else if (a == "--steps") {
                for (const std::string& item : items) {
                    const auto rate = parseNumber(item);
                    if (!rate || *rate < 1 || *rate > 1e5)
                        return usage("--steps expects steps per second from 1 to 100000, got '" + item + "'");
                    options.steps.push_back(1.0 / *rate);
                }
            } else if (a == "--out") {
                outDir = v;
            } else if (a == "--apply") {
                applyPath = v;
            } else if (a == "--error") {
                const auto kind = bench::parseStudyError(v);
                if (!kind)
                    return usage("--error expects total, integration or model, got '" + v + "'");
                options.error = *kind;
            } else if (a == "--repeats") {
                const auto n = parseNumber(v);
                if (!n || *n < 1 || *n > 100 || *n != std::floor(*n))
                    return usage("--repeats expects a whole number from 1 to 100, got '" + v + "'");
                options.repeats = int(*n);
            } else {
                target = parseNumber(v);
                if (!target || *target <= 0)
                    return usage("--target expects a positive number, got '" + v + "'");
            }
        } else if (!a.empty() && a[0] == '-') {
            return usage("unknown study argument '" + a + "'");
        } else if (scenePath.empty()) {
            scenePath = a;
        } else {
            return usage("unexpected argument '" + a + "'");
        }
    }
    if (scenePath.empty())
        return usage("study needs a SCENE file");
    if (!applyPath.empty() && !target)
        return usage("--apply needs --target: it writes the pick for that target");
    auto project = io::loadProject(scenePath);
    if (!project)
        return fail(project.message());
    const bench::StudyResult result = bench::runStudy(project->scene, options, std::cout);
    if (!outDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(outDir, ec);
        const std::filesystem::path dir(outDir);
        std::string command = "softtouch-cli study " + scenePath + " --out " + outDir + (options.quick ? " --quick" : "");
        if (options.error != bench::StudyError::Total)
            command += " --error " + std::string(bench::studyErrorName(options.error));
        if (Status s = io::writeFileAtomically(dir / "study.csv", bench::studyCsv(result)); !s)
            return fail(s.message());
        if (Status s = io::writeFileAtomically(dir / "study.md", bench::studyMarkdown(result, command)); !s)
            return fail(s.message());
        const auto gui = offscreenGuiApplication();
        if (const std::string error = bench::writeStudyPlot(result, (dir / "study.png").string()); !error.empty())
            return fail(error);
        std::printf("wrote %s, %s and %s\n", (dir / "study.csv").c_str(), (dir / "study.md").c_str(),
                    (dir / "study.png").c_str());
    }
    if (!target)
        return 0;
    const std::string errorName(bench::studyErrorName(result.error));
    if (*target >= result.restError && result.error == bench::StudyError::Total)
        std::printf("note: doing nothing at all (the rest pose) scores %.2e, within this target: the target asks for no "
                    "motion; this clip moves up to %.2e of the diagonal\n",
                    result.restError, result.motionAmplitude);
    const bench::StudyRow* pick = bench::cheapestWithin(result, *target);
    if (!pick)
        return fail("no setting reaches a " + errorName + " error of " + formatValue(*target) + " of the diagonal");
    std::printf("cheapest setting within %g of the diagonal (%s error): %s, dt = 1/%d s, %s lattice (%s error %.2e; "
                "%.2e s per simulated s)\n",
                *target, errorName.c_str(), std::string(integratorName(pick->integrator)).c_str(), int(std::lround(1.0 / pick->dt)),
                pick->resolution.c_str(), errorName.c_str(), pick->error(result.error), pick->costPerSecond);
    if (applyPath.empty())
        return 0;
    auto applied = bench::applySetting(project->scene, pick->setting());
    if (!applied)
        return fail(applied.message());
    io::Project out = project.value();
    out.scene = std::move(applied.value());
    if (Status s = out.clips.validate(out.scene); !s)
        return fail("the pick puts '" + out.scene.objects.front().name + "' on a " + pick->resolution +
                    " lattice, which the project's clips cannot follow: " + s.message());
    if (Status s = io::saveProject(out, applyPath); !s)
        return fail(s.message());
    // Re-measure the project as written: read back from the file, run as a bake runs it.
    auto written = io::loadProject(applyPath);
    if (!written)
        return fail(written.message());
    auto measured = bench::remeasure(written->scene, result);
    if (!measured)
        return fail(applyPath + ": " + measured.message());
    const double error = measured->error(result.error);
    std::printf("wrote %s; re-measured as written: total error %.2e (integration %.2e, model %.2e)\n", applyPath.c_str(),
                measured->total, measured->integration, measured->model);
    if (error > *target)
        return fail(applyPath + ": as written, the " + errorName + " error is " + std::to_string(error) + ", above the target " +
                    formatValue(*target));
    return 0;
}

}  // namespace softtouch::cli
