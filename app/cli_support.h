#pragma once
/// What every softtouch-cli subcommand shares: how errors are printed and how numbers are parsed.

#include "app/cli_usage.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <utility>

namespace softtouch::cli {

/// Prints "softtouch-cli: error: MESSAGE" and returns exit status 1 (a failure).
inline int fail(const std::string& message) {
    std::fprintf(stderr, "softtouch-cli: error: %s\n", message.c_str());
    return 1;
}

/// Prints a usage problem, the command's usage line (`synopsis`, what follows "softtouch-cli ") and where its help
/// is, and returns exit status 2 (bad usage). `command` empty: the top-level help.
inline int usageError(const std::string& message, const std::string& synopsis = {}, const std::string& command = {}) {
    std::fprintf(stderr, "softtouch-cli: %s\n", message.c_str());
    if (!synopsis.empty())
        std::fprintf(stderr, "Usage: softtouch-cli %s\n", synopsis.c_str());
    std::fprintf(stderr, "See 'softtouch-cli %s--help'.\n", command.empty() ? "" : (command + " ").c_str());
    return 2;
}

/// Prints "wrote FILE" for each of `files`; more than four (an OBJ sequence's frames) as the first and the
/// last with the count, not a line each.
inline void printWritten(std::span<const std::filesystem::path> files) {
    if (files.size() > 4) {
        std::printf("wrote %s ... %s (%zu files)\n", files.front().c_str(), files.back().c_str(), files.size());
        return;
    }
    for (const std::filesystem::path& file : files)
        std::printf("wrote %s\n", file.c_str());
}

/// Creates the folders an output path needs, as someone asking for `new/dir/fish.pc2` expects: its parent, or the
/// path itself when it names a folder (ends in '/'). Returns an error message (empty on success) and sets
/// `made` to the topmost folder it created (empty when all were there), which removeEmptyFolders() takes
/// away again after a failed command.
inline std::string makeOutputFolders(const std::string& out, std::filesystem::path& made) {
    namespace fs = std::filesystem;
    made.clear();
    const fs::path target = fs::path(out);
    fs::path folder = !out.empty() && out.back() == '/' ? target : target.parent_path();
    if (folder.empty())
        return {};
    std::error_code error;
    for (fs::path p = folder; !p.empty() && !fs::exists(p, error); p = p.parent_path()) {
        made = p;
        if (p == p.parent_path())
            break;
    }
    if (made.empty())
        return {};
    if (!fs::create_directories(folder, error) && error)
        return "cannot create the folder '" + folder.string() + "' for '" + out + "': " + error.message();
    return {};
}

/// Removes `made` (from makeOutputFolders()) when nothing but folders is inside it: a failed command leaves
/// no empty folders behind.
inline void removeEmptyFolders(const std::filesystem::path& made) {
    namespace fs = std::filesystem;
    if (made.empty())
        return;
    std::error_code error;
    for (fs::recursive_directory_iterator it(made, error), end; !error && it != end; it.increment(error))
        if (!it->is_directory(error))
            return;
    fs::remove_all(made, error);
}

/// A finite number spelled exactly by `text` (no trailing characters), or nothing.
inline std::optional<double> parseNumber(const std::string& text) {
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
        return std::nullopt;
    return value;
}

/// A number as a user would write it back (%g: 0, 0.001, 1e-300), not std::to_string's 0.000000.
inline std::string formatValue(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

/// "WxH" with whole numbers in [16, 8192] (picture and video sizes), or nothing.
inline std::optional<std::pair<int, int>> parseSize(const std::string& text) {
    const std::size_t x = text.find('x');
    if (x == std::string::npos)
        return std::nullopt;
    int w = 0, h = 0;
    const char* begin = text.data();
    const auto a = std::from_chars(begin, begin + x, w);
    const auto b = std::from_chars(begin + x + 1, begin + text.size(), h);
    if (a.ec != std::errc() || a.ptr != begin + x || b.ec != std::errc() || b.ptr != begin + text.size())
        return std::nullopt;
    if (w < 16 || h < 16 || w > 8192 || h > 8192)
        return std::nullopt;
    return std::pair{w, h};
}

}  // namespace softtouch::cli
