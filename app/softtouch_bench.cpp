// softtouch-bench: SoftTouch's measurements (bench, study, stability, modes). It links what the
// production front end does without: the benchmarks' peer (Bullet) and Qt's painter for the study plot
// and the captioned mode pictures. softtouch-cli starts it for these commands, so they are typed and
// documented as `softtouch-cli COMMAND`; run on its own it takes the same command lines.
#include "app/bench_commands.h"
#include "app/cli_support.h"
#include "app/cli_options.h"
#include "app/cli_usage.h"

#include <cstdio>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace {

using Run = int (*)(const std::vector<std::string>&);
constexpr std::pair<std::string_view, Run> kRuns[] = {
    {"bench", softtouch::cli::runBench},
    {"study", softtouch::cli::runStudy},
    {"stability", softtouch::cli::runStability},
    {"modes", softtouch::cli::runModes},
};

void printUsage(std::FILE* to) {
    std::fputs("softtouch-bench — SoftTouch's measurements: benchmarks, the speed/accuracy study, the stability grid and\n"
               "vibration modes. Usually started by softtouch-cli, which takes the same command lines.\n\nCommands:\n",
               to);
    for (const auto& [name, run] : kRuns)
        if (const auto* c = softtouch::cli::findCommand(name))
            std::fputs(softtouch::cli::helpEntry(c->command, c->summary).c_str(), to);
    std::fputs("\n'softtouch-cli COMMAND --help' for each command. Exit status: 0 on success, 1 on failure (one-line reason\n"
               "on stderr), 2 on bad usage (the reason and the command's usage line).\n",
               to);
}

}  // namespace

int main(int argc, char** argv) {
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
    for (const auto& [name, run] : kRuns)
        if (command == name)
            return run(args);
    return softtouch::cli::usageError("unknown command '" + command + "' (softtouch-bench runs bench, study, stability and modes)");
}
