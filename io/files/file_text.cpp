#include "io/files/file_text.h"

#include <charconv>
#include <string>

namespace softtouch::io::detail {

std::string quoted(const std::filesystem::path& path) {
    // Appended piece by piece: "'" + path.string() + "'" trips GCC 12's false -Wrestrict at -O3.
    std::string text = path.string();
    text.insert(text.begin(), '\'');
    text.push_back('\'');
    return text;
}

std::string formatNumber(double value) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

}  // namespace softtouch::io::detail
