#include "io/atomic_file.h"

#include "io/vertex_cache_internal.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace softtouch::io {

namespace {

std::string errnoText(int error) {
    return error != 0 ? std::generic_category().message(error) : std::string("unknown I/O error");
}

Status writeError(const std::filesystem::path& target, const std::string& reason) {
    return Status::error("cannot write " + detail::quoted(target) + ": " + reason);
}

/// Live temporaries, for the signal handler: a fixed table of heap copies of their paths, so the
/// handler only reads pointers and calls unlink() (both async-signal-safe). Best effort: a run with
/// more live temporaries than slots (an OBJ sequence of thousands of frames) leaves the rest to
/// removeStaleTemporaries on the next bake.
constexpr std::size_t kLiveSlots = 4096;
std::atomic<char*> g_live[kLiveSlots];

void remember(const std::filesystem::path& temporary) {
    char* copy = ::strdup(temporary.c_str());
    if (copy == nullptr)
        return;
    for (auto& slot : g_live) {
        char* expected = nullptr;
        if (slot.compare_exchange_strong(expected, copy))
            return;
    }
    std::free(copy);
}

extern "C" void removeLiveTemporaries(int signal) {
    for (auto& slot : g_live)
        if (const char* path = slot.load())
            ::unlink(path);
    ::signal(signal, SIG_DFL);
    ::raise(signal);
}

}  // namespace

namespace detail {

std::filesystem::path temporaryPathFor(const std::filesystem::path& target) {
    // The pid keeps two processes apart (and tells removeStaleTemporaries whose it is), the counter two
    // writers (or two staged OBJ frames) of one.
    static std::atomic<std::uint64_t> counter{0};
    std::filesystem::path temporary = target;
    temporary += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
    remember(temporary);
    return temporary;
}

void forgetTemporary(const std::filesystem::path& temporary) {
    for (auto& slot : g_live) {
        char* path = slot.load();
        if (path != nullptr && temporary == path && slot.compare_exchange_strong(path, nullptr)) {
            std::free(path);
            return;
        }
    }
}

}  // namespace detail

void removeTemporariesOnSignal() {
    for (int signal : {SIGINT, SIGTERM, SIGHUP})
        ::signal(signal, removeLiveTemporaries);
}

namespace {

/// True when no live process has this pid: none at all, or only a zombie (killed, not yet reaped: a
/// bake re-run right after a kill -9 of the one before meets it while the reaper has not run yet).
bool processIsGone(long pid) {
    if (::kill(pid_t(pid), 0) != 0)
        return errno == ESRCH;
    std::FILE* stat = std::fopen(("/proc/" + std::to_string(pid) + "/stat").c_str(), "r");
    if (!stat)
        return false;
    char state = 0;
    // "pid (comm) S ...": the state follows the last ')' (comm may hold spaces and parentheses).
    char line[512] = {};
    const bool read = std::fgets(line, sizeof line, stat) != nullptr;
    std::fclose(stat);
    if (const char* close = read ? std::strrchr(line, ')') : nullptr; close && close[1] == ' ')
        state = close[2];
    return state == 'Z' || state == 'X';
}

}  // namespace

void removeStaleTemporaries(const std::filesystem::path& target) {
    namespace fs = std::filesystem;
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    const std::string prefix = target.filename().string() + ".tmp-";
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind(prefix, 0) != 0)
            continue;
        // "<prefix><pid>-<n>…": remove it when that process is gone (kill(pid, 0) fails with ESRCH).
        const std::string rest = name.substr(prefix.size());
        const auto dash = rest.find('-');
        if (dash == std::string::npos || dash == 0 || rest.find_first_not_of("0123456789") != dash)
            continue;
        const long pid = std::strtol(rest.substr(0, dash).c_str(), nullptr, 10);
        if (pid > 0 && pid != long(::getpid()) && processIsGone(pid)) {
            std::error_code ignored;
            fs::remove(it->path(), ignored);
        }
    }
}

AtomicFile::AtomicFile(std::filesystem::path target) : m_target(std::move(target)) {}

AtomicFile::~AtomicFile() { discard(); }

Status AtomicFile::open() {
    discard();
    // The temporary sits beside the target so that the final rename stays within one file system
    // (rename() is only atomic there). O_EXCL: never write into a file someone else left behind
    // (a crashed run whose pid was reused); take the next name instead.
    for (int attempt = 0; attempt < 64; ++attempt) {
        const std::filesystem::path temporary = detail::temporaryPathFor(m_target);
        const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0) {
            const int error = errno;
            detail::forgetTemporary(temporary);
            if (error == EEXIST)
                continue;
            return writeError(m_target, errnoText(error));
        }
        // Keep the permissions of the file being replaced, as QSaveFile does; a new file gets
        // 0666 minus the umask like any other.
        struct stat existing {};
        if (::stat(m_target.c_str(), &existing) == 0 && S_ISREG(existing.st_mode)) {
            // Failing to copy them (someone else's file in our directory) is not worth failing the save.
            [[maybe_unused]] const int ignored = ::fchmod(fd, existing.st_mode & 07777);
        }
        m_file = ::fdopen(fd, "wb");
        if (m_file == nullptr) {
            const int error = errno;
            ::close(fd);
            std::error_code ignored;
            std::filesystem::remove(temporary, ignored);
            detail::forgetTemporary(temporary);
            return writeError(m_target, errnoText(error));
        }
        m_temporary = temporary;
        return Status::success();
    }
    return writeError(m_target, "no free temporary file name beside it");
}

Status AtomicFile::write(const void* data, std::size_t size) {
    if (m_file == nullptr)
        return writeError(m_target, "the file is not open");
    if (size == 0)
        return Status::success();
    errno = 0;
    if (std::fwrite(data, 1, size, m_file) != size) {
        const int error = errno;
        discard();
        return writeError(m_target, errnoText(error));
    }
    return Status::success();
}

Status AtomicFile::commit() {
    if (m_file == nullptr)
        return writeError(m_target, "the file is not open");
    // Flush and sync before the rename: otherwise a crash soon after could leave the new name
    // pointing at a file whose data never reached the disk, which is worse than the old file.
    // fsync's EINVAL means the file cannot be synced at all (a special file), which is no failure.
    int error = 0;
    if (std::fflush(m_file) != 0 || (::fsync(::fileno(m_file)) != 0 && errno != EINVAL))
        error = errno;
    if (std::fclose(m_file) != 0 && error == 0)
        error = errno;
    m_file = nullptr;
    if (error != 0) {
        discard();
        return writeError(m_target, errnoText(error));
    }
    std::error_code renameError;
    std::filesystem::rename(m_temporary, m_target, renameError);
    if (renameError) {
        discard();
        return Status::error("cannot replace " + detail::quoted(m_target) + ": " + renameError.message());
    }
    detail::forgetTemporary(m_temporary);
    m_temporary.clear();
    return Status::success();
}

void AtomicFile::discard() {
    if (m_file != nullptr) {
        std::fclose(m_file);
        m_file = nullptr;
    }
    if (!m_temporary.empty()) {
        std::error_code ignored;
        std::filesystem::remove(m_temporary, ignored);
        detail::forgetTemporary(m_temporary);
        m_temporary.clear();
    }
}

Status writeFileAtomically(const std::filesystem::path& path, std::string_view bytes) {
    AtomicFile file(path);
    if (Status s = file.open(); !s)
        return s;
    if (Status s = file.write(bytes.data(), bytes.size()); !s)
        return s;
    return file.commit();
}

}  // namespace softtouch::io
