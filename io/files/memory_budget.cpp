#include "io/files/memory_budget.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <sys/resource.h>

namespace softtouch::io {

namespace {

/// The value after `key` in a "Key:   123 kB" file (/proc/meminfo, /proc/self/status), in bytes.
std::optional<std::uint64_t> kilobytesField(const char* file, const std::string& key) {
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);)
        if (line.rfind(key, 0) == 0) {
            std::istringstream fields(line.substr(key.size()));
            std::uint64_t kb = 0;
            if (fields >> kb)
                return kb * 1024;
        }
    return std::nullopt;
}

/// A cgroup v2 file holding one number ("max" means none).
std::optional<std::uint64_t> cgroupNumber(const std::string& name) {
    std::ifstream in("/sys/fs/cgroup/" + name);
    std::string text;
    if (!(in >> text) || text == "max")
        return std::nullopt;
    try {
        return std::stoull(text);
    } catch (...) {
        return std::nullopt;
    }
}

std::string gigabytes(std::uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / 1e9);
    return text;
}

}  // namespace

std::optional<std::uint64_t> availableMemoryBytes() {
    std::optional<std::uint64_t> least = kilobytesField("/proc/meminfo", "MemAvailable:");
    auto take = [&](std::uint64_t bytes) { least = least ? std::min(*least, bytes) : bytes; };
    if (const auto max = cgroupNumber("memory.max"))
        take(*max - std::min(*max, cgroupNumber("memory.current").value_or(0)));
    rlimit limit{};
    if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
        const std::uint64_t mapped = kilobytesField("/proc/self/status", "VmSize:").value_or(0);
        take(std::uint64_t(limit.rlim_cur) - std::min<std::uint64_t>(limit.rlim_cur, mapped));
    }
    return least;
}

Status checkMemoryFor(std::uint64_t bytes, const std::string& what, const std::string& advice) {
    const auto available = availableMemoryBytes();
    if (!available || bytes <= *available)
        return Status::success();
    return Status::error(what + " needs about " + gigabytes(bytes) + " of memory and " + gigabytes(*available) +
                         " is available: " + advice);
}

}  // namespace softtouch::io
