// softtouch-cli: the headless front end of SoftTouch (bake, render, validate). Parses the subcommand only.
#include "app/cli_commands.h"
#include "app/cli_support.h"
#include "io/atomic_file.h"

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr const char* kTitle = "softtouch-cli — headless SoftTouch: simulate soft-body lattices and export vertex caches\n";

constexpr const char* kCommands = R"(  softtouch-cli --help | --version

Commands:
  bake       Simulate SCENE (*.softtouch) from rest and write a vertex cache, plus the rest mesh (OBJ)
             it matches beside it. 'softtouch-cli bake --help' for details.
  render     Simulate SCENE and write a video (MP4/H.264, GIF or PNG frames) drawn headless on the GPU
             (EGL; no X server needed). 'softtouch-cli render --help' for details.
  preview    Write a web page that plays an exported clip (skin, morphs, VAT or lattice cache) with
             three.js, as a game would. 'softtouch-cli preview --help'.
  modes      The lowest vibration modes of each object (frequency, damping ratio, shape) and what the
             scene's integrator and step do to them; --pictures draws the shapes headless.
             'softtouch-cli modes --help'.
  upgrade    Rewrite per-lattice (lattice-springs) materials as continuum ones that mean the same on
             every lattice, keeping mass, lowest mode and damping. 'softtouch-cli upgrade --help'.
  validate   Check project (*.softtouch), preset (*.stpreset) and trajectory (*.sttraj) files; print every problem found.
  preset     Share an object's setup (lattice, painted maps, drivers, clips) as a *.stpreset and apply
             one to another scene, remapped when the lattices differ. 'softtouch-cli preset --help'.
  bench      Measure step cost, deformation throughput and the paper's Table 1 against peers.
  study      The speed/accuracy trade: integrator x dt x lattice resolution against a converged reference.
  haptic     Run the 1 kHz haptic loop on SCENE's first object with a device plugin (docs/haptics.md).
  batch      Bake and render a clip library (scenes x presets x clips x formats) from a manifest, skipping
             what is up to date, locally or as a Slurm job array (docs/farm.md). 'softtouch-cli batch --help'.
  stability  Classify a grid of extreme stiffness, mass, damping and dt per integrator (docs/stability.md).

Exit status: 0 on success, 1 on failure (one-line reason on stderr), 2 on bad usage (the reason and
the command's usage line).
)";

/// The help: title, every command's usage line (app/cli_usage.h, shared with the usage errors), commands.
void printUsage(std::FILE* to) {
    std::fprintf(to, "%s\nUsage:\n", kTitle);
    for (const softtouch::cli::CommandSynopsis& s : softtouch::cli::kSynopses)
        std::fprintf(to, "  softtouch-cli %.*s\n", int(s.synopsis.size()), s.synopsis.data());
    std::fputs(kCommands, to);
}

}  // namespace

int main(int argc, char** argv) {
    // Ctrl+C or a kill while a bake or render writes removes its temporaries before the process ends.
    softtouch::io::removeTemporariesOnSignal();
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty()) {
        printUsage(stderr);
        return 2;
    }
    const std::string command = args.front();
    args.erase(args.begin());
    if (command == "--help" || command == "-h" || command == "help") {
        printUsage(stdout);
        return 0;
    }
    if (command == "--version") {
        std::puts("softtouch-cli 0.1.0");
        return 0;
    }
    if (command == "bake")
        return softtouch::cli::runBake(args);
    if (command == "render")
        return softtouch::cli::runRender(args);
    if (command == "preview")
        return softtouch::cli::runPreview(args);
    if (command == "validate")
        return softtouch::cli::runValidate(args);
    if (command == "preset")
        return softtouch::cli::runPreset(args);
    if (command == "bench")
        return softtouch::cli::runBench(args);
    if (command == "study")
        return softtouch::cli::runStudy(args);
    if (command == "stability")
        return softtouch::cli::runStability(args);
    if (command == "modes")
        return softtouch::cli::runModes(args);
    if (command == "upgrade")
        return softtouch::cli::runUpgrade(args);
    if (command == "batch")
        return softtouch::cli::runBatch(args);
    if (command == "haptic")
        return softtouch::cli::runHaptic(args);
    return softtouch::cli::usageError("unknown command '" + command + "'");
}
