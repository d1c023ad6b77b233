#pragma once
/// The subcommands softtouch-cli runs itself (app/bench_commands.h: those softtouch-bench runs). Each
/// takes its arguments (after the subcommand name) and returns the process exit code: 0 success,
/// 1 failure (a one-line reason on stderr), 2 bad usage.

#include <string>
#include <vector>

namespace softtouch::cli {

int runBake(const std::vector<std::string>& args);
int runValidate(const std::vector<std::string>& args);
int runRender(const std::vector<std::string>& args);
/// softtouch-cli preview: a web page that plays an exported clip with three.js.
int runPreview(const std::vector<std::string>& args);
int runPreset(const std::vector<std::string>& args);
int runHaptic(const std::vector<std::string>& args);
/// `softtouch-cli batch`: clip libraries from a manifest, locally or as a Slurm job array.
int runBatch(const std::vector<std::string>& args);
/// `softtouch-cli upgrade`: lattice-springs materials rewritten as continuum ones.
int runUpgrade(const std::vector<std::string>& args);

}  // namespace softtouch::cli
