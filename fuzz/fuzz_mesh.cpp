// Fuzz target: a mesh through SoftTouch's checks and assimp. The first byte picks the format (the
// importer goes by extension), the rest is the file.
#include "fuzz/fuzz_input.h"
#include "io/import/mesh_import.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1)
        return 0;
    static const char* const kExtensions[] = {".obj", ".ply", ".glb", ".gltf", ".stl", ".off"};
    const char* extension = kExtensions[data[0] % (sizeof kExtensions / sizeof *kExtensions)];
    const auto path = softtouch::fuzz::writeInput(data + 1, size - 1, extension);
    (void)softtouch::io::importMesh(path);
    return 0;
}
