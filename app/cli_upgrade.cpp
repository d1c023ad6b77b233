// `softtouch-cli upgrade`: rewrite a project's lattice-springs materials (values that belong to one
// lattice) as Continuum materials (values of the solid, the same on every lattice) that keep each
// body's mass, lowest mode and its damping (core/modes/material_conversion.h), printing what moved.
#include "app/cli_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"

#include "core/modes/material_conversion.h"
#include "io/documents/project_file.h"

#include <cstdio>

namespace softtouch::cli {
namespace {

constexpr const char* kUpgradeAbout = R"(Rewrite every lattice-springs material of SCENE (kg per node, N/m and N·s/m per spring: the meaning
of projects before version 3) as a continuum material (density kg/m³, Young's modulus Pa,
viscosity Pa·s, node damping rate 1/s) whose values no longer depend on the lattice. Painted maps
keep their ratios; each body keeps its total mass, its lowest mode's frequency and that mode's
damping ratios. Higher modes move: the table printed shows by how much. SCENE is not modified.
)";

}  // namespace

int runUpgrade(const std::vector<std::string>& args) {
    std::string scenePath, outPath;
    CommandLine line("upgrade", kUpgradeAbout, "Exit status: 0 on success, 1 when SCENE cannot be loaded, converted or written, 2 on bad usage.");
    line.positional("SCENE", scenePath, "The project to upgrade (*.softtouch).");
    line.text("--out", outPath, {"NEW.softtouch", "Where the upgraded project goes.", true});
    if (const auto exit = line.parse(args))
        return *exit;
    auto project = io::loadProject(scenePath);
    if (!project)
        return fail(project.message());
    for (SceneObject& object : project->scene.objects) {
        if (object.material.model == MaterialModel::Continuum) {
            std::printf("%s: already continuum\n", object.name.c_str());
            continue;
        }
        auto converted = continuumEquivalent(object.lattice, object.material);
        if (!converted)
            return fail(scenePath + ": object '" + object.name + "': " + converted.message());
        std::printf("%s: mode  before Hz (ζ)      after Hz (ζ)       change\n", object.name.c_str());
        for (std::size_t m = 0; m < converted->before.size() && m < converted->after.size(); ++m) {
            const VibrationMode& b = converted->before[m];
            const VibrationMode& c = converted->after[m];
            std::printf("  %zu   %8.4f (%.4f)   %8.4f (%.4f)   %+.1f%%\n", m + 1, b.frequencyHz, b.dampingRatio,
                        c.frequencyHz, c.dampingRatio, 100.0 * (c.frequencyHz / b.frequencyHz - 1.0));
        }
        object.material = std::move(converted->material);
    }
    if (Status s = io::saveProject(project.value(), outPath); !s)
        return fail(s.message());
    return 0;
}

}  // namespace softtouch::cli
