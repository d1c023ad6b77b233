// Fuzz target: a material or setup preset (*.stpreset) through both readers.
#include "fuzz/fuzz_input.h"
#include "io/documents/preset_file.h"
#include "io/documents/project_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace softtouch;
    const auto path = fuzz::writeInput(data, size, ".stpreset");
    (void)io::loadMaterialPreset(path);
    (void)io::loadSetupPreset(path);
    return 0;
}
