#pragma once
/// What every fuzz target shares: the fuzzed bytes become a file in a scratch folder laid out like
/// presets/ (scenes/, with meshes/ and materials/ beside it as links to the bundled ones), so the seed
/// projects' relative paths ("../meshes/guppy.obj") resolve and the mutations explore past the header.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace softtouch::fuzz {

/// The scratch folder (made once per process): <tmp>/softtouch-fuzz-<pid>/ with scenes/, out/ and
/// links to presets/meshes, materials, devices and setups.
const std::filesystem::path& scratch();

/// Writes the bytes to scratch()/scenes/input<extension> and returns that path.
std::filesystem::path writeInput(const std::uint8_t* data, std::size_t size, const std::string& extension);

}  // namespace softtouch::fuzz
