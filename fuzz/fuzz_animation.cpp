// Fuzz target: an animated import's request, the "animation" object of a project (its keys "take", "start",
// "end", "loop", "sampleRate" and "goal"; io/documents/project_file.cpp, io/import/animation_import.h). The input is that
// object's text, spliced into a small project on the bundled rigged guppy, which is loaded (the mesh imported
// and sampled in the importer's child). Not baked: the goal springs' stiffness is the simulator's and
// fuzz_project's to explore (a 1000 Hz goal takes 23 s for two frames under ASan, past the 20 s an input
// may take), and here every input should spend its time in the importer.
#include "fuzz/fuzz_input.h"
#include "io/documents/project_file.h"

#include <string>
#include <string_view>

namespace {

/// The project around the fuzzed object. The guppy's one take, "swim", is a second long: whatever the request
/// asks, the work is one second of samples at most (1,001 of 3,198 vertices), and the scratch folder links the
/// bundled meshes beside its scenes/ (fuzz/fuzz_input.h).
constexpr const char* kBefore = R"({"format": "softtouch-project", "version": 4,
  "objects": [{"name": "guppy", "mesh": "../meshes/guppy-rigged.glb", "animation": )";
constexpr const char* kAfter = R"(,
               "lattice": {"kind": "bezier", "nodes": [3, 3, 3], "padding": 0.02},
               "material": {"goalWeight": 0.5}}],
  "world": {"gravity": [0, 0, 0]},
  "simulation": {"integrator": "verlet"},
  "clip": {"frames": 2, "fps": 24}})";

/// True when `text` is one object, its braces and brackets balanced outside strings, and nothing but white
/// space after it: spliced in as the "animation" value, it cannot close that object and add keys or objects of
/// its own (fuzz_project explores the whole file). Its numbers and keys are not checked: 1e400 and a key
/// written twice reach SoftTouch's reader as they are.
bool isOneObject(std::string_view text) {
    const std::string_view space = " \t\r\n";
    std::size_t i = text.find_first_not_of(space);
    if (i == std::string_view::npos || text[i] != '{')
        return false;
    int depth = 0;
    bool inString = false;
    for (; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\')
                ++i;  // the escaped character, whatever it is
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '{' || c == '[') {
            ++depth;
        } else if ((c == '}' || c == ']') && --depth == 0) {
            break;
        }
    }
    return i < text.size() && text.find_first_not_of(space, i + 1) == std::string_view::npos;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace softtouch;
    const std::string_view animation(reinterpret_cast<const char*>(data), size);
    if (!isOneObject(animation))
        return 0;
    const std::string text = kBefore + std::string(animation) + kAfter;
    const auto path = fuzz::writeInput(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), ".softtouch");
    (void)io::loadProject(path);
    return 0;
}
