#pragma once
/// How much memory this process may still take, so that work sized by its input (a video frame of
/// 8192x8192) is refused with a reason before it is allocated, instead of dying half-way in an
/// allocator or a driver (docs/design/reliability.md, "Limits").

#include "core/base/result.h"

#include <cstdint>
#include <optional>
#include <string>

namespace softtouch::io {

/// The least of: the machine's available memory (/proc/meminfo MemAvailable), what this process's
/// control group still allows (memory.max less memory.current), and what its address-space limit
/// (RLIMIT_AS, `ulimit -v`, `prlimit --as`) leaves beside what it has mapped already. Nothing when none
/// of them can be read.
std::optional<std::uint64_t> availableMemoryBytes();

/// Ok when `bytes` fit in availableMemoryBytes(); otherwise "<what> needs about N GB of memory and
/// M GB is available", then `advice`.
Status checkMemoryFor(std::uint64_t bytes, const std::string& what, const std::string& advice);

}  // namespace softtouch::io
