// softtouch-cli study (run by softtouch-bench): the speed/accuracy trade of a scene, its plot and picks.
#include "app/bench_commands.h"
#include "app/cli_offscreen_gui.h"
#include "app/cli_support.h"
#include "analysis/study.h"
#include "io/atomic_file.h"
#include "io/project_file.h"
#include "ui/study_plot.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

namespace softtouch::cli {

int runStudy(const std::vector<std::string>& args) {
    const auto usage = [](const std::string& message) { return usageError(message, "study"); };
    std::string scenePath, outDir, applyPath;
    std::optional<double> target;
    analysis::StudyOptions options;
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
                const auto kind = analysis::parseStudyError(v);
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
    const analysis::StudyResult result = analysis::runStudy(project->scene, options, std::cout);
    if (!outDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(outDir, ec);
        const std::filesystem::path dir(outDir);
        std::string command = "softtouch-cli study " + scenePath + " --out " + outDir + (options.quick ? " --quick" : "");
        if (options.error != analysis::StudyError::Total)
            command += " --error " + std::string(analysis::studyErrorName(options.error));
        if (Status s = io::writeFileAtomically(dir / "study.csv", analysis::studyCsv(result)); !s)
            return fail(s.message());
        if (Status s = io::writeFileAtomically(dir / "study.md", analysis::studyMarkdown(result, command)); !s)
            return fail(s.message());
        const auto gui = offscreenGuiApplication();
        if (const std::string error = ui::writeStudyPlot(result, (dir / "study.png").string()); !error.empty())
            return fail(error);
        std::printf("wrote %s, %s and %s\n", (dir / "study.csv").c_str(), (dir / "study.md").c_str(),
                    (dir / "study.png").c_str());
    }
    if (!target)
        return 0;
    const std::string errorName(analysis::studyErrorName(result.error));
    if (*target >= result.restError && result.error == analysis::StudyError::Total)
        std::printf("note: doing nothing at all (the rest pose) scores %.2e, within this target: the target asks for no "
                    "motion; this clip moves up to %.2e of the diagonal\n",
                    result.restError, result.motionAmplitude);
    const analysis::StudyRow* pick = analysis::cheapestWithin(result, *target);
    if (!pick)
        return fail("no setting reaches a " + errorName + " error of " + formatValue(*target) + " of the diagonal");
    std::printf("cheapest setting within %g of the diagonal (%s error): %s, dt = 1/%d s, %s lattice (%s error %.2e; "
                "%.2e s per simulated s)\n",
                *target, errorName.c_str(), std::string(integratorName(pick->integrator)).c_str(), int(std::lround(1.0 / pick->dt)),
                pick->resolution.c_str(), errorName.c_str(), pick->error(result.error), pick->costPerSecond);
    if (applyPath.empty())
        return 0;
    auto applied = analysis::applySetting(project->scene, pick->setting());
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
    auto measured = analysis::remeasure(written->scene, result);
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
