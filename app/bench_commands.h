#pragma once
/// The subcommands softtouch-bench runs (softtouch-cli forwards them; app/cli_usage.h says which are
/// whose). Same contract as app/cli_commands.h: arguments after the name in, exit code out.

#include <string>
#include <vector>

namespace softtouch::cli {

int runBench(const std::vector<std::string>& args);
int runStudy(const std::vector<std::string>& args);
int runStability(const std::vector<std::string>& args);
int runModes(const std::vector<std::string>& args);

}  // namespace softtouch::cli
