#pragma once
/// Where both programs find their bundled files: <bin>/../share/softtouch/INSTALLED when installed
/// (`cmake --install`), else the source tree's SOURCE (a build run from its tree). Needs
/// SOFTTOUCH_SOURCE_DIR (app/CMakeLists.txt defines it for both programs).

#include <filesystem>
#include <string>
#include <system_error>

namespace softtouch::app {

inline std::filesystem::path bundledFolder(const std::string& installed, const std::string& source) {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const std::filesystem::path candidate = exe.parent_path() / "../share/softtouch" / installed;
        if (std::filesystem::is_directory(candidate, ec))
            return candidate.lexically_normal();
    }
    return std::filesystem::path(SOFTTOUCH_SOURCE_DIR) / source;
}

}  // namespace softtouch::app
