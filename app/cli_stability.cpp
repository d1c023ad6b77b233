// `softtouch-cli stability`: runs the stability grid (analysis/stability_grid.h), prints the counts and
// writes the docs page.
#include "app/bench_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"

#include "analysis/stability_grid.h"
#include "analysis/timer.h"
#include "io/files/atomic_file.h"

#include <cstdio>
#include <optional>

namespace softtouch::cli {
namespace {

constexpr const char* kStabilityAbout = R"(Run every integrator on a small dragged lattice over a grid of stiffness (1e-2 .. 1e7 N/m), anchor mass
ratio (1 .. 1e6), node mass (1e-6 .. 1e3 kg), damping (0 .. 1e3 N·s/m; undamped bodies also from a 5%
deformation) and time step (0.1x, 1x, 10x the explicit bound, 1/24 s), and classify each run: stable,
bounded, caught (the guard substepped, refused or rolled back, and said so) or failed. Prints the counts
per integrator; the full grid takes about a minute and a half on two cores.
)";

constexpr const char* kStabilityAfter = R"(Exit status: 0 when the grid ran (failed runs are reported, not an error), 1 when FILE.md cannot be
written, 2 on bad usage.
)";

}  // namespace

int runStability(const std::vector<std::string>& args) {
    analysis::StabilityGridOptions options;
    std::string outPath;
    CommandLine line("stability", kStabilityAbout, kStabilityAfter);
    line.text("--out", outPath,
              {"FILE.md", "Also write the report (method, classes, tables, every failed run), atomically. "
                          "docs/measurements/stability.md is this report for the full grid."});
    line.flag("--quick", options.quick, "The small grid the tests use (seconds).");
    if (const auto exit = line.parse(args))
        return *exit;

    // Open the output first so that a bad path fails in a second, not after the whole grid.
    std::optional<io::AtomicFile> file;
    if (!outPath.empty()) {
        file.emplace(outPath);
        if (Status s = file->open(); !s) {
            std::fprintf(stderr, "softtouch-cli: error: %s\n", s.message().c_str());
            return 1;
        }
    }

    std::printf("stability grid (%s): running...\n", options.quick ? "quick" : "full");
    std::fflush(stdout);
    const analysis::Stopwatch watch;
    const std::vector<analysis::StabilityCell> cells = analysis::runStabilityGrid(options);
    const double seconds = watch.seconds();

    std::printf("%zu runs in %.1f s\n\n  %-18s %7s %7s %7s %7s %7s\n", cells.size(), seconds, "integrator", "stable",
                "bounded", "caught", "failed", "runs");
    int failed = 0;
    bool implicitAllStable = true;
    for (IntegratorKind kind : integratorKinds()) {
        const analysis::OutcomeCounts c = analysis::countOutcomes(cells, kind);
        std::printf("  %-18s %7d %7d %7d %7d %7d\n", std::string(integratorName(kind)).c_str(), c.stable, c.bounded,
                    c.caught, c.failed, c.total());
        failed += c.failed;
        if (kind == IntegratorKind::ImplicitEuler && c.stable != c.total())
            implicitAllStable = false;
    }
    if (failed > 0)
        std::fprintf(stderr,
                     "softtouch-cli: warning: %d runs failed (non-finite output or unreported energy growth)%s\n",
                     failed, outPath.empty() ? "; --out FILE.md lists them" : "");
    if (!implicitAllStable)
        std::fprintf(stderr, "softtouch-cli: warning: implicit-euler is not stable in every run\n");

    if (!outPath.empty()) {
        std::string command = "softtouch-cli stability";
        if (options.quick)
            command += " --quick";
        command += " --out " + outPath;
        const std::string text = analysis::stabilityMarkdown(cells, command);
        Status s = file->write(text.data(), text.size());
        if (s)
            s = file->commit();
        if (!s) {
            std::fprintf(stderr, "softtouch-cli: error: %s\n", s.message().c_str());
            return 1;
        }
        std::printf("\nwrote %s\n", outPath.c_str());
    }
    return 0;
}

}  // namespace softtouch::cli
