#pragma once
/// `softtouch-cli bench`: the speed figures of SoftTouch, each beside its baseline from the same run
/// (these machines are shared and noisy, so only same-run ratios are comparable across runs).
/// JSON keys: docs/measurements/benchmarks.md.

#include "bench/haptic_bench.h"

#include "core/scene/scene.h"

#include <nlohmann/json.hpp>

#include <ostream>

namespace softtouch::bench {

/// What to run.
struct BenchOptions {
    bool quick = false;  ///< Small sizes only (seconds instead of minutes); for CI smoke runs.
    std::string only;    ///< Empty: every section; otherwise one JSON key ("haptic", "table1", …) alone.
    std::vector<HapticBenchScene> hapticScenes; ///< Scenes for the haptic section (the app loads the star);
                                                ///< the million-triangle scene is always added.
    int hapticPriority = 80;  ///< SCHED_FIFO priority the haptic loop asks for; 0: normal scheduling. [0, 99].
    /// The scenes the "edit" section paints on (the app loads the angelfish, and the rigged guppy on an 8x8x8 net).
    std::vector<const Scene*> editScenes;
};

/// Runs every benchmark, prints a readable report to `out` as it goes, returns the JSON document.
nlohmann::json runBench(const BenchOptions& options, std::ostream& out);

}  // namespace softtouch::bench
