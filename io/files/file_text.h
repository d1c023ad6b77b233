#pragma once
/// How io/ names files and numbers in its messages, and the temporaries its writers publish from. Internal to
/// io/: include it from io/*.cpp only.

#include <filesystem>
#include <string>

namespace softtouch::io::detail {

/// "'<path>'", the way every io/ message names a file.
std::string quoted(const std::filesystem::path& path);

/// A number the way a person writes it ("24", "0.5", "nan"), without std::to_string's "24.000000".
std::string formatNumber(double value);

/// A fresh name beside `target`, "<target>.tmp-<pid>-<counter>", unique within this process. The
/// counter is shared by every caller so AtomicFile temporaries and staged OBJ frames never collide.
/// Defined in atomic_file.cpp.
std::filesystem::path temporaryPathFor(const std::filesystem::path& target);
/// The temporary was published or removed: the signal handler no longer needs to remove it.
void forgetTemporary(const std::filesystem::path& temporary);

}  // namespace softtouch::io::detail
