// Fuzz target: the compressed-GLB reader (io/import/gltf_meshopt.h), which the preview page's inspection runs on any
// .glb it is given, and the packer on whatever that reader accepts.
#include "fuzz/fuzz_input.h"
#include "io/import/gltf_meshopt.h"

#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace softtouch;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    if (auto expanded = io::expandGlb(bytes, "input.glb"))
        (void)io::compressGlb(expanded.value(), "expanded.glb");
    return 0;
}
