// softtouch-cli: the headless front end of SoftTouch (bake, render, validate). Parses the subcommand only.
#include "app/cli_commands.h"
#include "io/atomic_file.h"

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr const char* kUsage = R"(softtouch-cli — headless SoftTouch: simulate soft-body lattices and export vertex caches

Usage:
  softtouch-cli bake SCENE --out FILE [--clip NAME] [--frames N] [--fps F] [--format pc2|mdd|objseq|gltf|glb|vat|lattice] [--threads N]
  softtouch-cli render SCENE --out FILE.mp4|FILE.gif|DIR/ [--clip NAME] [--size WxH] [--fps F] [--frames N] [--crf N]
  softtouch-cli validate FILE...
  softtouch-cli modes SCENE [--count N] [--object NAME] [--pictures PREFIX [--size WxH] [--amplitude F]]
  softtouch-cli upgrade SCENE --out NEW.softtouch
  softtouch-cli preset export SCENE --out P.stpreset | preset apply P.stpreset SCENE --out NEW.softtouch
  softtouch-cli bench [--json FILE] [--quick] [--only KEY]
  softtouch-cli study SCENE [--out DIR] [--quick] [--error KIND] [--target ERROR [--apply OUT]]
  softtouch-cli stability [--out FILE.md] [--quick]
  softtouch-cli haptic SCENE [--device NAME] [--device-arg ARG] [--seconds S] [--manual] [--record FILE]
  softtouch-cli --help | --version

Commands:
  bake       Simulate SCENE (*.softtouch) from rest and write a vertex cache, plus the rest mesh (OBJ)
             it matches beside it. 'softtouch-cli bake --help' for details.
  render     Simulate SCENE and write a video (MP4/H.264, GIF or PNG frames) drawn headless on the GPU
             (EGL; no X server needed). 'softtouch-cli render --help' for details.
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
  stability  Classify a grid of extreme stiffness, mass, damping and dt per integrator (docs/stability.md).

Exit status: 0 on success, 1 on failure (one-line reason on stderr), 2 on bad usage.
)";

}  // namespace

int main(int argc, char** argv) {
    // Ctrl+C or a kill while a bake or render writes removes its temporaries before the process ends.
    softtouch::io::removeTemporariesOnSignal();
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty()) {
        std::fputs(kUsage, stderr);
        return 2;
    }
    const std::string command = args.front();
    args.erase(args.begin());
    if (command == "--help" || command == "-h" || command == "help") {
        std::fputs(kUsage, stdout);
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
    if (command == "haptic")
        return softtouch::cli::runHaptic(args);
    std::fprintf(stderr, "softtouch-cli: error: unknown command '%s'; see 'softtouch-cli --help'\n", command.c_str());
    return 2;
}
