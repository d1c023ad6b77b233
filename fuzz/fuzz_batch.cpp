// Fuzz target: a batch manifest (*.stbatch) read and planned, beside a scene it can name
// ("star.softtouch", the bundled star-drag). What a plan must never do, whatever the manifest says,
// aborts: an output or a stamp outside the library, a job id outside [A-Za-z0-9._-].
#include "fuzz/fuzz_input.h"
#include "io/files/input_file.h"
#include "io/pipeline/batch_plan.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace softtouch;
    namespace fs = std::filesystem;
    static const bool sceneCopied = [] {
        std::error_code ec;
        fs::copy_file(fs::path(SOFTTOUCH_SOURCE_DIR) / "presets/scenes/star-drag.softtouch",
                      fuzz::scratch() / "scenes/star.softtouch", fs::copy_options::overwrite_existing, ec);
        return !ec;
    }();
    (void)sceneCopied;
    const auto path = fuzz::writeInput(data, size, ".stbatch");
    auto manifest = io::loadBatchManifest(path);
    if (!manifest) {
        // validate's reader is load's, listing every problem; on a manifest that loads it would only plan
        // it a second time (each scene's meshes imported again), so it runs on the others alone.
        (void)io::validateBatchManifest(path);
        return 0;
    }
    auto jobs = io::planBatch(manifest.value());
    if (!jobs)
        return 0;
    const fs::path root = manifest->outputRoot.lexically_normal();
    for (const io::BatchJob& job : jobs.value()) {
        if (!io::liesInside(job.output.lexically_normal(), root) ||
            !io::liesInside(io::batchStampPath(manifest.value(), job).lexically_normal(), root))
            std::abort();
        if (!std::all_of(job.id.begin(), job.id.end(),
                         [](unsigned char c) { return std::isalnum(c) || c == '.' || c == '-' || c == '_'; }))
            std::abort();
    }
    return 0;
}
