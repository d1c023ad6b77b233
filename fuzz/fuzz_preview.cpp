// Fuzz target: the preview's glTF reader (io/export/preview_gltf.h) through inspectPreviewClip, as `softtouch-cli
// preview` runs it on a clip from anyone. The first byte picks .gltf or .glb, the rest is the file; it lies
// in a scratch folder with the bundled presets linked beside it, so a URI that leaves the folder has files
// to find.
#include "fuzz/fuzz_input.h"
#include "io/pipeline/clip_preview.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1)
        return 0;
    const auto path = softtouch::fuzz::writeInput(data + 1, size - 1, data[0] % 2 == 0 ? ".gltf" : ".glb");
    (void)softtouch::io::inspectPreviewClip(path);
    return 0;
}
