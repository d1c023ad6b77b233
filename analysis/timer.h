#pragma once
/// Wall-clock timing helpers for the benchmarks (never used by tests: timings are too noisy to assert).

#include <algorithm>
#include <chrono>
#include <vector>

namespace softtouch::analysis {

/// Seconds since construction.
class Stopwatch {
public:
    Stopwatch() : m_start(std::chrono::steady_clock::now()) {}
    double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count(); }

private:
    std::chrono::steady_clock::time_point m_start;
};

/// Runs `body` (which does `batch` units of work) repeatedly for at least `minSeconds` and at least
/// `minRuns` times; returns the best time per unit in seconds. The minimum is the least noisy
/// estimate on a shared machine: noise only ever adds time.
template <typename Body>
double bestSecondsPerUnit(Body&& body, int batch, double minSeconds, int minRuns = 3) {
    double best = 1e300;
    Stopwatch total;
    for (int run = 0; run < minRuns || total.seconds() < minSeconds; ++run) {
        Stopwatch w;
        body();
        best = std::min(best, w.seconds() / batch);
    }
    return best;
}

}  // namespace softtouch::analysis
