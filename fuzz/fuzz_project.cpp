// Fuzz target: a project file loaded, and baked for three frames as `softtouch-cli bake` would when it loads;
// when it does not, through validate's reader too (io::validateFile: project, material and setup presets alike).
#include "fuzz/fuzz_input.h"
#include "io/documents/project_file.h"
#include "io/pipeline/bake.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <functional>

namespace {

/// Lattices above this are skipped here, before loading, not refused by SoftTouch: they are valid,
/// only slow (a 24x24x24 B-spline's body takes seconds to build under the sanitizers), and a fuzzer must
/// run hundreds of inputs a second to learn anything. test_cli covers large lattices.
constexpr int kMaxFuzzedNodes = 1000;

/// True when the text asks for a lattice above kMaxFuzzedNodes ("nodes": [a, b, c] anywhere).
bool asksForALargeLattice(const std::uint8_t* data, std::size_t size) {
    const nlohmann::json doc = nlohmann::json::parse(data, data + size, nullptr, false);
    bool large = false;
    std::function<void(const nlohmann::json&, int)> visit = [&](const nlohmann::json& v, int depth) {
        if (depth > 16)  // SoftTouch's files nest 6 deep; deeper text is the reader's to refuse
            return;
        if (v.is_object()) {
            if (auto it = v.find("nodes"); it != v.end() && it->is_array() && it->size() == 3) {
                double count = 1.0;
                for (const auto& n : *it)
                    count *= n.is_number() ? std::abs(n.get<double>()) : 1.0;
                large = large || count > kMaxFuzzedNodes;
            }
            for (const auto& [key, child] : v.items())
                visit(child, depth + 1);
        } else if (v.is_array()) {
            for (const auto& child : v)
                visit(child, depth + 1);
        }
    };
    if (!doc.is_discarded())
        visit(doc, 0);
    return large;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace softtouch;
    if (asksForALargeLattice(data, size))
        return 0;
    const auto path = fuzz::writeInput(data, size, ".softtouch");
    // validate's reader is load's, collecting every problem instead of stopping at the first: it adds nothing
    // on a file that loads, and would import its meshes a second time (each in a child process).
    auto project = io::loadProject(path);
    if (!project) {
        (void)io::validateFile(path);
        return 0;
    }
    for (const SceneObject& object : project->scene.objects)
        if (object.lattice.nodeCount() > kMaxFuzzedNodes)
            return 0;
    io::BakeOptions options;
    options.output = fuzz::scratch() / "out" / "bake.pc2";
    options.frames = 3;
    options.clips = &project->clips;
    options.threads = 1;
    (void)io::bake(project->scene, options);
    return 0;
}
