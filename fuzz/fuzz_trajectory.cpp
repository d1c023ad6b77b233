// Fuzz target: a recorded device trajectory (*.sttraj), as the scripted device and `haptic` read it.
#include "fuzz/fuzz_input.h"
#include "io/documents/trajectory_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = softtouch::fuzz::writeInput(data, size, ".sttraj");
    (void)softtouch::io::loadTrajectory(path);
    return 0;
}
