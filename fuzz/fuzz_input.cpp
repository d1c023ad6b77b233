#include "fuzz/fuzz_input.h"

#include <cstdlib>
#include <fstream>
#include <system_error>
#include <unistd.h>

namespace softtouch::fuzz {

const std::filesystem::path& scratch() {
    static const std::filesystem::path dir = [] {
        namespace fs = std::filesystem;
        const fs::path root = fs::temp_directory_path() / ("softtouch-fuzz-" + std::to_string(::getpid()));
        std::error_code ec;
        fs::create_directories(root / "scenes", ec);
        fs::create_directories(root / "out", ec);
        for (const char* folder : {"meshes", "materials", "devices", "setups"})
            fs::create_directory_symlink(fs::path(SOFTTOUCH_SOURCE_DIR) / "presets" / folder, root / folder, ec);
        std::atexit([] { std::error_code ignored; fs::remove_all(scratch(), ignored); });
        return root;
    }();
    return dir;
}

std::filesystem::path writeInput(const std::uint8_t* data, std::size_t size, const std::string& extension) {
    const std::filesystem::path path = scratch() / "scenes" / ("input" + extension);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

}  // namespace softtouch::fuzz
