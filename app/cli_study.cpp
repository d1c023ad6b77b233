// softtouch-cli study (run by softtouch-bench): the speed/accuracy trade of a scene, its plot and picks.
#include "analysis/study.h"
#include "analysis/timer.h"
#include "app/bench_commands.h"
#include "app/cli_offscreen_gui.h"
#include "app/cli_options.h"
#include "app/cli_support.h"
#include "io/documents/project_file.h"
#include "io/export/vertex_cache.h"
#include "io/files/atomic_file.h"
#include "io/pipeline/bake.h"
#include "io/pipeline/reference_cache.h"
#include "ui/study_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <unistd.h>

namespace softtouch::cli {

namespace {

/// The words of a comma-separated list ("verlet,xpbd").
std::vector<std::string> commaSeparated(const std::string& text) {
    std::vector<std::string> items;
    for (std::size_t start = 0; start <= text.size();) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        items.push_back(text.substr(start, comma - start));
        start = comma + 1;
    }
    return items;
}

/// What `bake` writes by default, a PC2 cache and its rest mesh, into a scratch folder that goes when this does:
/// the study times it with every run, so its costs are what a bake pays (StudyOptions::write).
class ScratchBake {
public:
    explicit ScratchBake(const Scene& scene) {
        std::error_code ec;
        m_folder = std::filesystem::temp_directory_path(ec) / ("softtouch-study-" + std::to_string(::getpid()));
        std::filesystem::create_directories(m_folder, ec);
        for (const SceneObject& object : scene.objects)
            (void)io::appendToRestMesh(m_rest, *object.mesh);
        if (m_rest.normals.size() != m_rest.positions.size())
            m_rest.computeNormals();
    }
    ~ScratchBake() {
        std::error_code ec;
        std::filesystem::remove_all(m_folder, ec);
    }
    ScratchBake(const ScratchBake&) = delete;
    ScratchBake& operator=(const ScratchBake&) = delete;
    const std::filesystem::path& folder() const { return m_folder; }

    Status write(const analysis::ClipMeshFrames& clip, double fps) {
        const auto writer = io::makeCacheWriter(io::CacheFormat::Pc2, m_rest);
        if (Status s = writer->begin(m_folder / "clip.pc2", {m_rest.positions.size(), std::size_t(clip.frames), fps, 0.0}); !s)
            return s;
        std::vector<Vec3f> frame(m_rest.positions.size());
        for (int f = 0; f < clip.frames; ++f) {
            auto out = frame.begin();
            for (std::size_t i = 0; i < clip.positions.size(); ++i)
                out = std::ranges::copy(clip.frame(i, f), out).out;
            if (Status s = writer->writeFrame(frame); !s) {
                writer->abort();
                return s;
            }
        }
        if (Status s = io::writeObj(m_folder / "clip.obj", m_rest); !s) {
            writer->abort();
            return s;
        }
        return writer->finish();
    }

private:
    std::filesystem::path m_folder;
    Mesh m_rest;
};

}  // namespace

int runStudy(const std::vector<std::string>& args) {
    std::string scenePath, outDir, applyPath;
    std::optional<double> target, repeats;
    analysis::StudyOptions options;
    CommandLine line("study", R"(For every integrator x dt (1/1000 .. 1/24 s) x lattice (2^3, 3^3, 4^3, 6^3, 8^3 Bezier; 6^3, 8^3
B-spline) on springs, and implicit Euler x dt x the lattices of at most 216 nodes on the solid
element (64 with --quick), every object on that lattice, the clip played as bake exports it: its
cost (wall time per second of clip of what bake pays: physics, mesh deformation and writing a PC2
cache and its rest mesh; fastest of the repeats) and the mesh's error against the converged solid
(the solid element on 4^3, 6^3, 8^3 Bezier nets at 1/4000 s, then 1/8000 s; its estimated
distance from the limit is printed): total, integration (against the same lattice converged in
time) and model (that converged run against the solid), RMS relative to the mesh's bounding-box
diagonal, the worst object's; energy drift, amplitude lost per period and frequency error in free
vibration.
)");
    line.positional("SCENE", scenePath, "The project to measure (*.softtouch).");
    line.flag("--quick", options.quick, "Fewer steps and lattices (3 x 3), the same clip, a coarser reference (3^3, 4^3, 6^3).");
    line.text("--out", outDir, {"DIR", "Write DIR/study.csv, DIR/study.md and DIR/study.png (error against cost, Pareto front)."});
    line.text("--clip", options.clip, {"NAME", "The clip to measure (default: what bake plays, the default clip or the drivers)."});
    std::vector<int> referenceNets;
    line.value("--reference-nets", [&referenceNets](const std::string& v) {
        referenceNets.clear();
        for (const std::string& item : commaSeparated(v)) {
            double n = 0.0;
            if (!readNumber(item, {2, 8}, n).empty() || n != std::floor(n) || (!referenceNets.empty() && int(n) <= referenceNets.back()))
                return "expects rising node counts from 2 to 8 separated by commas, got '" + v + "'";
            referenceNets.push_back(int(n));
        }
        return std::string();
    }, {"N,N,...", "The reference's Bezier nets, nodes per axis, coarsest first (default 4,6,8; the last is the "
                   "reference, the others say how far it is from the limit)."});
    line.number("--repeats", repeats, {1, 100, true}, {"N", "Timed runs per setting, the cost is the fastest (default 5)."});
    line.value("--error", [&options](const std::string& v) {
        const auto kind = analysis::parseStudyError(v);
        if (!kind)
            return "expects total, integration or model, got '" + v + "'";
        options.error = *kind;
        return std::string();
    }, {"total|integration|model", "The error the Pareto front and --target use (default total)."});
    line.value("--lattices", [&options](const std::string& v) {
        for (const std::string& item : commaSeparated(v)) {
            const bool bezier = item.rfind("bezier", 0) == 0, bspline = item.rfind("bspline", 0) == 0;
            const auto n = bezier || bspline ? parseNumber(item.substr(bezier ? 6 : 7)) : std::nullopt;
            const int nodes = n && *n >= 0 && *n <= 1000 ? int(*n) : 0;
            const LatticeShape shape{bezier ? LatticeKind::Bezier : LatticeKind::BSpline, {nodes, nodes, nodes}};
            if (!n || *n != std::floor(*n) || !shape.validate())
                return "expects bezierN or bsplineN (N nodes per axis) separated by commas, got '" + item + "'";
            options.lattices.push_back(shape);
        }
        return std::string();
    }, {"L", "The lattices instead of the grid's: e.g. bezier2,bezier4,bspline10 (n^3 nodes)."});
    line.value("--integrators", [&options](const std::string& v) {
        for (const std::string& item : commaSeparated(v)) {
            const auto kind = parseIntegratorKind(item);
            if (!kind)
                return "expects integrator names separated by commas, got '" + item + "'";
            options.integrators.push_back(*kind);
        }
        return std::string();
    }, {"I", "The integrators instead of all four: e.g. verlet,xpbd."});
    line.value("--steps", [&options](const std::string& v) {
        for (const std::string& item : commaSeparated(v)) {
            double rate = 0.0;
            if (!readNumber(item, {1, 1e5}, rate).empty())
                return "expects steps per second from 1 to 100000 separated by commas, got '" + item + "'";
            options.steps.push_back(1.0 / rate);
        }
        return std::string();
    }, {"S", "The steps per second instead of the grid's: e.g. 24,240."});
    line.value("--elements", [&options](const std::string& v) {
        for (const std::string& item : commaSeparated(v)) {
            if (item != "springs" && item != "solid")
                return "expects springs, solid or springs,solid, got '" + item + "'";
            const BodyElement element = item == "solid" ? BodyElement::Solid : BodyElement::Springs;
            if (std::find(options.elements.begin(), options.elements.end(), element) == options.elements.end())
                options.elements.push_back(element);
        }
        return std::string();
    }, {"E", "springs, solid or springs,solid (default); with --lattices or --integrators the solid element runs "
             "those (XPBD aside)."});
    line.number("--target", target, {0, std::numeric_limits<double>::infinity(), false, false},
                {"ERROR", "Print the cheapest setting whose error is at most ERROR (e.g. 0.01); refused, with nothing "
                          "written, when doing nothing meets it or the reference cannot certify it."});
    line.text("--apply", applyPath,
              {"OUT.softtouch", "With --target: write SCENE with that setting (integrator, dt; every object moved to its "
                                "lattice and element, material carried over) to OUT, read it back and re-measure it as written."});
    if (const auto exit = line.parse(args))
        return *exit;
    if (repeats)
        options.repeats = int(*repeats);
    if (!applyPath.empty() && !target)
        return line.usage("--apply needs --target: it writes the pick for that target");
    auto project = io::loadProjectToRun(scenePath);
    if (!project)
        return fail(project.message());
    if (options.quick)
        options.reference = analysis::quickReference();
    if (!referenceNets.empty())
        options.reference.nodes = referenceNets;
    // The converged solid takes minutes: kept by content between studies of the same scene and clip.
    const std::filesystem::path cacheFolder = io::referenceCacheFolder();
    const io::KeptReference kept = io::findKeptReference(cacheFolder, project.value(), options.clip, std::span(&options.reference, 1));
    const std::string& key = kept.key;
    options.given = kept.reference;
    if (options.given)
        std::printf("converged reference: %s, from the cache (%s)\n", options.given->description.c_str(),
                    (cacheFolder / key).c_str());
    options.target = target;  // a target the reference cannot certify stops the study before its grid
    ScratchBake scratch(project->scene);
    const auto played = analysis::clipToPlay(project->scene, project->clips, options.clip);
    const double fps = played ? played->fps : 24.0;  // no such clip: the study says so before anything is timed
    options.write = [&](const analysis::ClipMeshFrames& frames) { return scratch.write(frames, fps); };
    options.written = "a PC2 cache and its rest mesh, as `bake` does by default";
    const analysis::StudyResult result = analysis::runStudy(project->scene, project->clips, options, std::cout);
    if (!options.given && result.reference && !key.empty()) {
        if (Status s = io::writeCachedReference(cacheFolder, key, *result.reference); !s)
            std::fprintf(stderr, "note: the reference is not kept for the next study: %s\n", s.message().c_str());
    }
    if (!result.failure.empty())
        return fail(scenePath + ": " + result.failure);
    const std::string errorName(analysis::studyErrorName(result.error));
    // A refused target stopped the study above, before anything is written.
    if (!outDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(outDir, ec);
        const std::filesystem::path dir(outDir);
        std::string command = "softtouch-cli study " + scenePath + " --out " + outDir + (options.quick ? " --quick" : "");
        if (!options.clip.empty())
            command += " --clip " + options.clip;
        if (repeats)
            command += " --repeats " + std::to_string(options.repeats);
        if (options.error != analysis::StudyError::Total)
            command += " --error " + std::string(analysis::studyErrorName(options.error));
        if (Status s = io::writeFileAtomically(dir / "study.csv", analysis::studyCsv(result)); !s)
            return fail(s.message());
        if (Status s = io::writeFileAtomically(dir / "study.md", analysis::studyMarkdown(result, command)); !s)
            return fail(s.message());
        const auto gui = offscreenApplication();
        if (const std::string error = ui::writeStudyPlot(result, (dir / "study.png").string()); !error.empty())
            return fail(error);
        std::printf("wrote %s, %s and %s\n", (dir / "study.csv").c_str(), (dir / "study.md").c_str(),
                    (dir / "study.png").c_str());
    }
    if (!target)
        return 0;
    const analysis::StudyRow* pick = analysis::cheapestWithin(result, *target);
    if (!pick)
        return fail("no setting reaches a " + errorName + " error of " + formatValue(*target) + " of the diagonal");
    std::printf("cheapest setting within %g of the diagonal (%s error): %s, dt = 1/%d s, %s lattice, %s (%s error %.2e; "
                "%.2e s per second of clip)\n",
                *target, errorName.c_str(), std::string(integratorName(pick->integrator)).c_str(), int(std::lround(1.0 / pick->dt)),
                analysis::latticeShapeName(pick->lattice).c_str(),
                pick->element == BodyElement::Solid ? "solid element" : "springs", errorName.c_str(), pick->error(result.error),
                pick->costPerSecond);
    if (applyPath.empty())
        return 0;
    auto applied = analysis::applySetting(project->scene, pick->setting());
    if (!applied)
        return fail(applied.message());
    io::Project out = project.value();
    out.scene = std::move(applied.value());
    if (Status s = out.clips.validate(out.scene); !s)
        return fail("the pick puts the objects on a " + pick->resolution +
                    " lattice, which the project's clips cannot follow: " + s.message());
    if (Status s = io::saveProject(out, applyPath); !s)
        return fail(s.message());
    // Re-measure the project as written: read back from the file, run as a bake runs it.
    auto written = io::loadProject(applyPath);
    if (!written)
        return fail(written.message());
    auto measured = analysis::remeasure(written->scene, written->clips, result);
    if (!measured)
        return fail(applyPath + ": " + measured.message());
    const double error = measured->error(result.error);
    std::printf("wrote %s; re-measured as written: total error %.2e (integration %.2e, model %.2e)\n", applyPath.c_str(),
                measured->total, measured->integration, measured->model);
    if (error > *target)
        return fail(applyPath + ": as written, the " + errorName + " error is " + std::to_string(error) + ", above the target " +
                    formatValue(*target));
    // The printed cost against a real bake of the written project (one deformation thread, as the study times it).
    io::BakeOptions bakeOptions;
    bakeOptions.output = scratch.folder() / "applied.pc2";
    bakeOptions.clips = &written->clips;
    bakeOptions.clip = options.clip;
    bakeOptions.threads = 1;
    double fastest = std::numeric_limits<double>::infinity();
    for (int r = 0; r < options.repeats; ++r) {
        const analysis::Stopwatch watch;
        if (auto baked = io::bake(written->scene, bakeOptions); !baked)
            return fail(applyPath + ": " + baked.message());
        fastest = std::min(fastest, watch.seconds());
    }
    std::printf("baked as written: %.2e s per second of clip, fastest of %d (the study: %.2e)\n",
                fastest / result.clip.seconds(), options.repeats, pick->costPerSecond);
    return 0;
}

}  // namespace softtouch::cli
