#pragma once
/// Atomic file writes: everything goes to a temporary file beside the target, which replaces the
/// target only on commit() (flush, fsync, rename). A failed or abandoned write leaves the previous
/// file untouched and no temporary behind.

#include "core/result.h"

#include <cstdio>
#include <filesystem>
#include <string_view>

namespace softtouch::io {

/// One file being written atomically.
class AtomicFile {
public:
    explicit AtomicFile(std::filesystem::path target);
    ~AtomicFile();  ///< Discards the temporary if commit() was not reached.
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// Creates the temporary file (binary mode).
    Status open();
    /// Writes raw bytes; errors name the target file.
    Status write(const void* data, std::size_t size);
    /// Flushes, syncs and renames over the target.
    Status commit();
    /// Removes the temporary; the target is untouched.
    void discard();

    const std::filesystem::path& target() const { return m_target; }

private:
    std::filesystem::path m_target;
    std::filesystem::path m_temporary;
    std::FILE* m_file = nullptr;
};

/// Writes `bytes` to `path` in one atomic step (open, write, commit).
Status writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

}  // namespace softtouch::io
