#pragma once
/// What every softtouch-cli subcommand shares: how errors are printed and how numbers are parsed.

#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace softtouch::cli {

/// Prints "softtouch-cli: error: MESSAGE" and returns exit status 1 (a failure).
inline int fail(const std::string& message) {
    std::fprintf(stderr, "softtouch-cli: error: %s\n", message.c_str());
    return 1;
}

/// Prints a usage problem pointing at the command's help and returns exit status 2 (bad usage).
/// `command` empty: the top-level help.
inline int usageError(const std::string& message, const std::string& command = {}) {
    std::fprintf(stderr, "softtouch-cli: %s; see 'softtouch-cli %s--help'\n", message.c_str(),
                 command.empty() ? "" : (command + " ").c_str());
    return 2;
}

/// A finite number spelled exactly by `text` (no trailing characters), or nothing.
inline std::optional<double> parseNumber(const std::string& text) {
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
        return std::nullopt;
    return value;
}

}  // namespace softtouch::cli
