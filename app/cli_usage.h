#pragma once
/// The one-line synopsis of every softtouch-cli subcommand: the top-level help lists them, and every
/// bad-usage error (exit 2) prints the one of its subcommand, so the two never disagree.

#include "io/export/export_formats.h"

#include <array>
#include <string>
#include <string_view>

namespace softtouch::cli {

/// Which program runs a subcommand. The measurements live in softtouch-bench, which alone links the
/// Bullet peer and Qt's painter (plots, captioned pictures); softtouch-cli runs that program, installed
/// beside it, for them, so every command is typed as `softtouch-cli COMMAND`.
enum class Program { Cli, Bench };

struct CommandSynopsis {
    std::string_view command;  ///< The subcommand, as typed.
    std::string_view synopsis; ///< What follows "softtouch-cli " in its usage line; "{formats}" stands for the
                               ///< export registry's names (io/export/export_formats.h), see synopsisText().
    Program program = Program::Cli;
};

inline constexpr std::array<CommandSynopsis, 12> kSynopses{{
    {"bake", "bake SCENE --out FILE [--clip NAME] [--frames N] [--fps F] [--format {formats}] [--error E] [--targets K | --bones K] [--compress] [--object NAME | --each-object] [--groups] [--threads N]"},
    {"render", "render SCENE --out FILE.mp4|FILE.gif|DIR/ [--clip NAME] [--size WxH] [--fps F] [--frames N] [--crf N]"},
    {"preview", "preview CLIP --out DIR [--size WxH]"},
    {"validate", "validate FILE..."},
    {"modes", "modes SCENE [--count N] [--object NAME] [--pictures PREFIX [--size WxH] [--amplitude F]]", Program::Bench},
    {"upgrade", "upgrade SCENE --out NEW.softtouch"},
    {"preset", "preset export SCENE --out P.stpreset | preset apply P.stpreset SCENE --out NEW.softtouch"},
    {"bench", "bench [--json FILE] [--quick] [--only KEY]", Program::Bench},
    {"study", "study SCENE [--out DIR] [--quick] [--error KIND] [--target ERROR [--apply OUT]]", Program::Bench},
    {"stability", "stability [--out FILE.md] [--quick]", Program::Bench},
    {"batch", "batch plan|run|slurm|check MANIFEST.stbatch [--library DIR] [--jobs N | --job ID] [--out DIR] [--force]"},
    {"haptic", "haptic SCENE [--device NAME] [--device-arg ARG] [--seconds S] [--manual] [--record FILE]"},
}};

/// The entry of `command`, or nullptr when there is none.
inline const CommandSynopsis* findCommand(std::string_view command) {
    for (const CommandSynopsis& s : kSynopses)
        if (s.command == command)
            return &s;
    return nullptr;
}

/// A synopsis as printed: "{formats}" replaced by "pc2|mdd|…|lattice".
inline std::string synopsisText(std::string_view synopsis) {
    std::string text(synopsis);
    constexpr std::string_view kFormats = "{formats}";
    if (const std::size_t at = text.find(kFormats); at != std::string::npos)
        text.replace(at, kFormats.size(), io::exportFormatNames("|", "|"));
    return text;
}

/// The synopsis of `command` as printed, or empty when there is none.
inline std::string synopsisOf(std::string_view command) {
    for (const CommandSynopsis& s : kSynopses)
        if (s.command == command)
            return synopsisText(s.synopsis);
    return {};
}

}  // namespace softtouch::cli
