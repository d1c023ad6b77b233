#pragma once
/// What SoftTouch agrees to read, checked before anything is allocated (docs/design/reliability.md, "Limits").
/// Every file a reader opens goes through `checkInputFile` first: only regular files (a FIFO would block
/// forever, /dev/zero never ends), none larger than the reader's limit.

#include "core/base/result.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace softtouch::io {

inline constexpr std::uintmax_t kMiB = std::uintmax_t(1) << 20;
/// Projects, presets and recorded trajectories. The largest legitimate one is a project whose painted
/// maps cover a 64x64x64 lattice: 4 maps x 262,144 numbers, about 20 MB.
inline constexpr std::uintmax_t kMaxJsonFileBytes = 256 * kMiB;
/// Arrays and objects nested deeper than this are refused before parsing: SoftTouch's own files nest
/// at most 6 deep, and printing a 100,000-deep value overflowed the stack.
inline constexpr int kMaxJsonDepth = 64;
/// Keys (object members) and values (array elements and members) in one JSON file, counted before it
/// is parsed. SoftTouch's own files hold a few hundred keys; the painted maps of a 64x64x64 lattice are
/// ~1.1 million values, an hour of 1 kHz device recording ~18 million. Parsed, a key costs ~100 bytes
/// and a value 16 or more: these keep a file's tree under about 1 GB.
inline constexpr std::size_t kMaxJsonKeys = 1'000'000;
inline constexpr std::size_t kMaxJsonValues = 32'000'000;
/// Mesh files handed to assimp (a 10-million-triangle binary PLY is about 250 MB).
inline constexpr std::uintmax_t kMaxMeshFileBytes = 1024 * kMiB;

/// Whether `text` (a name or path from a file) holds a control character: a NUL would cut it short for
/// the system, a newline start a command of its own in a script, and no file SoftTouch writes has one.
bool hasControlCharacter(std::string_view text);

/// `text` for a message, its control characters shown as '?', so that a hostile name cannot cut the line.
std::string shownName(std::string text);

/// Whether `path` lies below `folder` (not `folder` itself), both absolute and normalised (lexically or
/// canonically): where a file a shared input names must stay (docs/design/reliability.md, "Confinement").
bool liesInside(const std::filesystem::path& path, const std::filesystem::path& folder);

/// Ok when `path` names a regular file of at most `maxBytes` bytes; otherwise what is wrong, worded to
/// follow the file's name ("is not a regular file (a FIFO)", "does not exist").
Status checkInputFile(const std::filesystem::path& path, std::uintmax_t maxBytes);

/// The whole file, after checkInputFile (a file that grows past the limit while read is refused too);
/// errors are worded as checkInputFile's.
Result<std::string> readInputFile(const std::filesystem::path& path, std::uintmax_t maxBytes);

}  // namespace softtouch::io
