#pragma once
/// Atomic file writes: everything goes to a temporary file beside the target, which replaces the
/// target only on commit() (flush, fsync, rename). A failed or abandoned write leaves the previous
/// file untouched and no temporary behind.

#include "core/base/result.h"

#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
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

/// Temporaries ("<target>.tmp-<pid>-<n>") live from creation to commit or discard; a process stopped in
/// between would leave them. On SIGINT, SIGTERM or SIGHUP every live temporary is removed, then the
/// process ends as the signal would have ended it. A crash (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT)
/// removes them too, then goes to the handler that was there before. The CLI installs this at start.
void removeTemporariesOnSignal();

/// A child process that must not outlive this one (a batch job): on SIGINT, SIGTERM or SIGHUP it gets
/// the same signal and is waited for before this process ends, so it publishes nothing after the
/// command has returned. forgetChildProcess() once it has been reaped.
void stopChildProcessOnSignal(int pid);
void forgetChildProcess(int pid);

/// Removes the temporaries of `target` left by processes that no longer run (a kill -9, a power cut);
/// a bake calls it for every file it is about to write.
void removeStaleTemporaries(const std::filesystem::path& target);

/// The same for every target in `folder` whose file name `isTarget` accepts, in one pass over the
/// folder: a bake of many files (an OBJ sequence) sweeps them all, including frames a killed run wrote
/// beyond the ones this run writes.
void removeStaleTemporaries(const std::filesystem::path& folder, const std::function<bool(const std::string&)>& isTarget);

}  // namespace softtouch::io
