// softtouch-cli bench (run by softtouch-bench): step cost, throughput and Table 1 against peers.
#include "app/bench_commands.h"
#include "app/bundled_paths.h"
#include "app/cli_options.h"
#include "app/cli_support.h"
#include "bench/bench.h"
#include "core/body/lattice_body.h"
#include "io/documents/project_file.h"
#include "io/files/atomic_file.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <algorithm>
#include <set>
#include <vector>

namespace softtouch::cli {

int runBench(const std::vector<std::string>& args) {
    bench::BenchOptions options;
    std::string jsonPath;
    std::filesystem::path hapticScene;
    std::optional<double> priority;
    CommandLine line("bench", R"(Lattice step cost per integrator, deformation throughput against a plain scalar kernel,
the paper's Table 1 redone (lattice vs global and local mass-spring vs Bullet btSoftBody),
and the cost of unused features. Every figure comes with its baseline from the same run.
)");
    line.text("--json", jsonPath, {"FILE", "Also write the results as JSON (keys: docs/measurements/benchmarks.md)."});
    line.flag("--quick", options.quick, "Small sizes only (seconds, not minutes).");
    static const std::vector<std::string> sections = {"lattice_step_us", "lattice_step_us_8x4x4", "lattice_step_us_8x8x8",
                                                      "features", "deform", "table1", "edit", "haptic"};
    std::string sectionNames;
    for (const std::string& section : sections)
        sectionNames += (sectionNames.empty() ? "" : ", ") + section;
    line.value("--only", [&options, sectionNames](const std::string& v) {
        if (std::find(sections.begin(), sections.end(), v) == sections.end())
            return "expects one of " + sectionNames + ", got '" + v + "'";
        options.only = v;
        return std::string();
    }, {"KEY", "One section: " + sectionNames + "."});
    line.value("--haptic-scene", [&hapticScene](const std::string& v) {
        hapticScene = v;
        return std::string();
    }, {"FILE", "Scene whose first object the haptic loop runs on, besides a generated 1,000,000-triangle one "
                "(default presets/scenes/star-drag.softtouch)."});
    line.number("--haptic-priority", priority, {0, 99, true},
                {"N", "SCHED_FIFO priority the haptic loop asks for (default 80; 0: normal)."});
    if (const auto exit = line.parse(args))
        return *exit;
    if (priority)
        options.hapticPriority = int(*priority);
    // A bundled scene from the working directory (the repository root), else beside the program.
    const auto bundledScene = [](const std::string& file) {
        const std::filesystem::path local = "presets/scenes/" + file;
        return std::filesystem::exists(local) ? local : app::bundledFolder("presets", "presets") / "scenes" / file;
    };
    std::optional<io::Project> star;
    if (options.only.empty() || options.only == "haptic") {
        if (hapticScene.empty())
            hapticScene = bundledScene("star-drag.softtouch");
        auto project = io::loadProject(hapticScene);
        if (!project)
            return fail(project.message());
        star = std::move(project.value());
        options.hapticScenes.push_back({hapticScene.stem().string(), &star->scene, Vec3(0.95, 0.95, 0.5)});
    }
    std::optional<io::Project> fish, guppy;
    if (options.only.empty() || options.only == "edit") {
        auto project = io::loadProject(bundledScene("angelfish-swim.softtouch"));  // 7,280 triangles
        if (!project)
            return fail(project.message());
        fish = std::move(project.value());
        options.editScenes.push_back(&fish->scene);
        // The rigged guppy (its own animation, painted goal weights) on an 8x8x8 net: the heaviest edit an
        // animator makes on a bundled scene.
        auto rigged = io::loadProject(bundledScene("guppy-rigged.softtouch"));
        if (!rigged)
            return fail(rigged.message());
        guppy = std::move(rigged.value());
        SceneObject& object = guppy->scene.objects.front();
        const Lattice fine = Lattice::create({LatticeKind::Bezier, {8, 8, 8}}, object.lattice.box()).value();
        object.material = resampleMaterial(object.lattice, object.material, fine, true);
        object.lattice = fine;
        options.editScenes.push_back(&guppy->scene);
    }
    const nlohmann::json result = bench::runBench(options, std::cout);
    if (!jsonPath.empty()) {
        if (Status s = io::writeFileAtomically(jsonPath, result.dump(2) + "\n"); !s)
            return fail(s.message());
        std::printf("\nwrote %s\n", jsonPath.c_str());
    }
    return 0;
}

}  // namespace softtouch::cli
