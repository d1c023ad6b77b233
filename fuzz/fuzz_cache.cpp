// Fuzz target: the readers of SoftTouch's own exports (PC2, MDD, lattice cache), which tests and the
// editor's re-import use, and of the study's reference cache. The first byte picks the reader; for the
// reference cache the next 16 are the key the file is stored under.
#include "fuzz/fuzz_input.h"
#include "io/export/lattice_cache.h"
#include "io/export/vertex_cache.h"
#include "io/pipeline/reference_cache.h"

#include <filesystem>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace softtouch;
    if (size < 1)
        return 0;
    switch (data[0] % 4) {
    case 0: (void)io::readPc2(fuzz::writeInput(data + 1, size - 1, ".pc2")); break;
    case 1: (void)io::readMdd(fuzz::writeInput(data + 1, size - 1, ".mdd")); break;
    case 2: (void)io::readLatticeCache(fuzz::writeInput(data + 1, size - 1, ".lattice.bin")); break;
    default: {
        if (size < 17)
            return 0;
        const std::string key(reinterpret_cast<const char*>(data + 1), 16);
        if (key.find_first_not_of("0123456789abcdef") != std::string::npos)
            return 0;
        const auto written = fuzz::writeInput(data + 17, size - 17, ".streference");
        std::error_code ec;
        std::filesystem::rename(written, written.parent_path() / (key + ".streference"), ec);
        (void)io::readCachedReference(written.parent_path(), key);
        break;
    }
    }
    return 0;
}
