#pragma once
/// Checks a mesh file's own promises before assimp reads it. Assimp allocates what a header announces:
/// a 182-byte PLY claiming 2e9 vertices took > 20 GB, and a PLY announcing 100 vertices with 8 present
/// imported the 8. These checks compare what the header announces with what the file can hold.

#include "core/base/result.h"

#include <filesystem>

namespace softtouch::io {

/// Ok unless `path` (a regular file already checked by checkInputFile) is a PLY whose header announces
/// more elements than its body holds (ASCII: one line per element; binary: the elements' fixed bytes),
/// or a GLB whose stated lengths exceed the file. Other formats pass (assimp's validation sees them).
Status checkMeshFileIsWhole(const std::filesystem::path& path);

}  // namespace softtouch::io
