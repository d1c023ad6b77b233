#include "io/files/atomic_file.h"

#include "io/files/file_text.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
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

/// Child processes to stop with this one (pids; 0: a free slot).
constexpr std::size_t kChildSlots = 256;
std::atomic<int> g_children[kChildSlots];

/// The signals a stop arrives by, and the crashes a process can die of.
constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};
constexpr int kCrashSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
/// What handled each crash signal before (a sanitizer's report, a crash reporter), called after ours.
struct sigaction g_previousCrashAction[std::size(kCrashSignals)];

/// unlink() each live temporary: async-signal-safe, for both handlers below.
void unlinkLiveTemporaries() {
    for (auto& slot : g_live)
        if (const char* path = slot.load())
            ::unlink(path);
}

extern "C" void removeLiveTemporaries(int signal) {
    // kill() and waitpid() are async-signal-safe: each child ends (removing its own temporaries) before
    // this process does, so nothing it publishes arrives after the command has returned.
    for (auto& slot : g_children)
        if (const int pid = slot.load(); pid > 0)
            ::kill(pid_t(pid), signal);
    for (auto& slot : g_children)
        if (const int pid = slot.load(); pid > 0)
            while (::waitpid(pid_t(pid), nullptr, 0) < 0 && errno == EINTR) {
            }
    unlinkLiveTemporaries();
    ::signal(signal, SIG_DFL);
    ::raise(signal);
}

/// A crash removes the temporaries too, then goes on as it would have:
/// to the handler installed before (ASan's report), or the default action (a core dump).
extern "C" void removeTemporariesOnCrash(int signal, siginfo_t* info, void* context) {
    unlinkLiveTemporaries();
    for (std::size_t i = 0; i < std::size(kCrashSignals); ++i) {
        if (kCrashSignals[i] != signal)
            continue;
        const struct sigaction& previous = g_previousCrashAction[i];
        if ((previous.sa_flags & SA_SIGINFO) && previous.sa_sigaction) {
            previous.sa_sigaction(signal, info, context);
            return;
        }
        if (previous.sa_handler != SIG_DFL && previous.sa_handler != SIG_IGN && previous.sa_handler != nullptr) {
            previous.sa_handler(signal);
            return;
        }
    }
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

void stopChildProcessOnSignal(int pid) {
    for (auto& slot : g_children) {
        int expected = 0;
        if (slot.compare_exchange_strong(expected, pid))
            return;
    }
}

void forgetChildProcess(int pid) {
    for (auto& slot : g_children) {
        int expected = pid;
        if (slot.compare_exchange_strong(expected, 0))
            return;
    }
}

void removeTemporariesOnSignal() {
    for (int signal : kStopSignals)
        ::signal(signal, removeLiveTemporaries);
    for (std::size_t i = 0; i < std::size(kCrashSignals); ++i) {
        struct sigaction action = {};
        action.sa_sigaction = removeTemporariesOnCrash;
        action.sa_flags = SA_SIGINFO | SA_NODEFER;
        sigemptyset(&action.sa_mask);
        ::sigaction(kCrashSignals[i], &action, &g_previousCrashAction[i]);
    }
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
    const std::string name = target.filename().string();
    removeStaleTemporaries(target.parent_path(), [&](const std::string& targetName) { return targetName == name; });
}

void removeStaleTemporaries(const std::filesystem::path& where, const std::function<bool(const std::string&)>& isTarget) {
    namespace fs = std::filesystem;
    const fs::path folder = where.empty() ? fs::path(".") : where;
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        // "<target>.tmp-<pid>-<n>" (a staged OBJ frame being written: "<target>.tmp-<pid>-<n>.tmp-<pid>-<m>"):
        // remove it when that process is gone (kill(pid, 0) fails with ESRCH).
        const auto tmp = name.find(".tmp-");
        if (tmp == std::string::npos || tmp == 0 || !isTarget(name.substr(0, tmp)))
            continue;
        const std::string rest = name.substr(tmp + 5);
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
