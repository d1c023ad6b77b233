// Fuzz target: the readers of SoftTouch's own exports (PC2, MDD, lattice cache), which tests and the
// editor's re-import use. The first byte picks the reader.
#include "fuzz/fuzz_input.h"
#include "io/lattice_cache.h"
#include "io/vertex_cache.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace softtouch;
    if (size < 1)
        return 0;
    switch (data[0] % 3) {
    case 0: (void)io::readPc2(fuzz::writeInput(data + 1, size - 1, ".pc2")); break;
    case 1: (void)io::readMdd(fuzz::writeInput(data + 1, size - 1, ".mdd")); break;
    default: (void)io::readLatticeCache(fuzz::writeInput(data + 1, size - 1, ".lattice.bin")); break;
    }
    return 0;
}
