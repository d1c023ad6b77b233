#pragma once
/// A minimal fork-join parallel loop over std::thread. Work is split into fixed, contiguous ranges,
/// so results never depend on scheduling (each index is written by exactly one thread).

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace softtouch {

/// Number of threads to use for `requested` (<= 0 means all hardware threads).
inline int resolveThreadCount(int requested) {
    if (requested > 0)
        return requested;
    return std::max(1, int(std::thread::hardware_concurrency()));
}

/// Calls body(begin, end) on `threads` contiguous ranges covering [0, count). Runs inline when one
/// thread is asked for or the range is too small to be worth a thread.
template <typename Body>
void parallelFor(std::size_t count, int threads, std::size_t minPerThread, Body&& body) {
    const std::size_t useful = std::max<std::size_t>(1, count / std::max<std::size_t>(1, minPerThread));
    const std::size_t n = std::min<std::size_t>(std::size_t(resolveThreadCount(threads)), useful);
    if (n <= 1) {
        body(std::size_t(0), count);
        return;
    }
    std::vector<std::jthread> workers;
    workers.reserve(n - 1);
    for (std::size_t t = 1; t < n; ++t)
        workers.emplace_back([&body, t, n, count] { body(count * t / n, count * (t + 1) / n); });
    body(std::size_t(0), count / n);
}

}  // namespace softtouch
