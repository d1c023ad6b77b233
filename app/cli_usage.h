#pragma once
/// The subcommands of softtouch-cli: which program runs each and what it is for, in a line. The top-level
/// help lists them; each command's usage line and options come from its own declarations (app/cli_options.h),
/// printed by `softtouch-cli COMMAND --help` and by every usage error of that command.

#include <array>
#include <string_view>

namespace softtouch::cli {

/// Which program runs a subcommand. The measurements live in softtouch-bench, which alone links the
/// Bullet peer and Qt's painter (plots, captioned pictures); softtouch-cli runs that program, installed
/// beside it, for them, so every command is typed as `softtouch-cli COMMAND`.
enum class Program { Cli, Bench };

struct CommandSummary {
    std::string_view command;  ///< The subcommand, as typed.
    std::string_view summary;  ///< What it does, for the top-level help.
    Program program = Program::Cli;
};

inline constexpr std::array<CommandSummary, 12> kCommands{{
    {"bake", "Simulate a scene (*.softtouch) and write a clip in one of the export formats (vertex caches, glTF, "
             "vertex animation textures, lattice caches), with the rest mesh it matches beside it."},
    {"render", "Simulate a scene and write a video (MP4/H.264, GIF or PNG frames) drawn headless on the GPU (EGL; no X "
               "server needed)."},
    {"preview", "Write a web page that plays an exported clip (skin, morphs, VAT or lattice cache) with three.js, as a "
                "game would."},
    {"validate", "Check project (*.softtouch), preset (*.stpreset), trajectory (*.sttraj) and batch manifest (*.stbatch) "
                 "files and print every problem found; of a mesh file, its vertices, triangles and animation takes."},
    {"modes", "The lowest vibration modes of each object (frequency, damping ratio, shape) and what the scene's "
              "integrator and step do to them; --pictures draws the shapes headless.", Program::Bench},
    {"upgrade", "Rewrite per-lattice (lattice-springs) materials as continuum ones that mean the same on every lattice, "
                "keeping mass, lowest mode and damping."},
    {"preset", "Share an object's setup (lattice, painted maps, drivers, clips) as a *.stpreset, and apply a setup "
               "(remapped when the lattices differ) or a material preset to an object of a scene."},
    {"bench", "Measure step cost, deformation throughput, the haptic loop and the paper's Table 1 against peers.",
     Program::Bench},
    {"study", "The speed/accuracy trade: integrator x step x lattice x element against a converged solid, with the "
              "cheapest setting for an error target.", Program::Bench},
    {"stability", "Classify a grid of extreme stiffness, mass, damping and step per integrator.", Program::Bench},
    {"batch", "Bake and render a clip library (scenes x presets x clips x formats) from a manifest, skipping what is up "
              "to date, locally or as a Slurm job array (docs/farm.md)."},
    {"haptic", "Run the 1 kHz haptic loop on a scene's first object with a device plugin (docs/haptics.md)."},
}};

/// The entry of `command`, or nullptr when there is none.
inline const CommandSummary* findCommand(std::string_view command) {
    for (const CommandSummary& c : kCommands)
        if (c.command == command)
            return &c;
    return nullptr;
}

}  // namespace softtouch::cli
