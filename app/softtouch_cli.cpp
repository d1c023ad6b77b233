// softtouch-cli: the headless front end of SoftTouch (bake, render, validate, ...). Parses the subcommand
// only. It links no Qt Gui and no benchmark peer, so a farm node needs neither: the measurements run in
// softtouch-bench, which it starts in its place (app/cli_usage.h says which commands are whose).
#include "app/cli_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"
#include "app/cli_usage.h"
#include "io/files/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace {

using Run = int (*)(const std::vector<std::string>&);
constexpr std::pair<std::string_view, Run> kRuns[] = {
    {"bake", softtouch::cli::runBake},       {"render", softtouch::cli::runRender},   {"preview", softtouch::cli::runPreview},
    {"validate", softtouch::cli::runValidate}, {"preset", softtouch::cli::runPreset}, {"upgrade", softtouch::cli::runUpgrade},
    {"batch", softtouch::cli::runBatch},     {"haptic", softtouch::cli::runHaptic},
};

/// Replaces this process with softtouch-bench (beside this program, as built and as installed) running
/// the same command line; returns only when that program cannot be started.
int runInBenchProgram(char** argv) {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::filesystem::path bench = self.parent_path() / "softtouch-bench";
    if (ec || !std::filesystem::is_regular_file(bench, ec))
        return softtouch::cli::fail(std::string("'") + argv[1] + "' runs in softtouch-bench, which is not beside softtouch-cli (" +
                                    bench.string() + ")");
    std::vector<char*> args{const_cast<char*>(bench.c_str())};
    for (char** a = argv + 1; *a; ++a)
        args.push_back(*a);
    args.push_back(nullptr);
    std::fflush(nullptr);
    ::execv(bench.c_str(), args.data());
    return softtouch::cli::fail("cannot run " + bench.string() + ": " + std::strerror(errno));
}

constexpr const char* kTitle = "softtouch-cli — headless SoftTouch: simulate soft-body lattices and export vertex caches\n";

constexpr const char* kAfter = R"(
'softtouch-cli COMMAND --help' shows a command's usage line and every option.

bench, study, stability and modes run in softtouch-bench, installed beside this program: it alone links
the benchmarks' peers (Bullet) and Qt's painter for plots and pictures; this program starts it for them.

Exit status: 0 on success, 1 on failure (one-line reason on stderr), 2 on bad usage (the reason and
the command's usage line).
)";

/// The help: title, how to call, every command with what it is for (app/cli_usage.h).
void printUsage(std::FILE* to) {
    std::fprintf(to, "%s\nUsage: softtouch-cli COMMAND ARGUMENTS [OPTIONS]\n       softtouch-cli --help | --version\n\nCommands:\n",
                 kTitle);
    for (const softtouch::cli::CommandSummary& c : softtouch::cli::kCommands)
        std::fputs(softtouch::cli::helpEntry(c.command, c.summary).c_str(), to);
    std::fputs(kAfter, to);
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
    for (const auto& [name, run] : kRuns)
        if (command == name) {
            // Limits are checked before anything large is allocated; should one still be missed, the
            // command fails with a reason instead of aborting (and temporaries go with their writers).
            try {
                return run(args);
            } catch (const std::bad_alloc&) {
                return softtouch::cli::fail("out of memory: the input asks for more than this machine can hold");
            }
        }
    if (const auto* entry = softtouch::cli::findCommand(command); entry && entry->program == softtouch::cli::Program::Bench)
        return runInBenchProgram(argv);
    return softtouch::cli::usageError("unknown command '" + command + "'");
}
