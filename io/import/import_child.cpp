// The importer's child process: started, fed its request, watched, and its answer or failure read back
// (io/import/isolated_import.h). Where the importer program (softtouch-import) is installed beside the running
// one, the child is that program, started with posix_spawn: it begins with one thread. A fork() of this process
// (the fallback, and what runIsolated() does for a test's own function) copies a process whose other threads
// (the GL driver's, the editor's mode analysis) may hold a lock at that moment, and the sanitizers' allocators of
// clang 14 and GCC 12 take no lock across fork(): such a child hung in its first allocation now and then.

#include "io/import/isolated_import.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <system_error>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace softtouch::io {

namespace {

/// The child's end of its progress pipe (reportImportProgress); -1 in any process that is not an importer child.
int progressFd = -1;

/// How an importer child exits when it could not send its answer, when `produce` threw, and (the program)
/// when its request did not decode.
constexpr int kChildCouldNotSend = 3;
constexpr int kChildThrew = 4;
constexpr int kChildBadRequest = 5;
/// The file descriptor the importer program beats its progress on.
constexpr int kProgramProgressFd = 3;

/// In the child: says why `produce` threw, on the error pipe (its stderr), and exits. Only write(2): after a
/// std::bad_alloc, building a message could throw again.
[[noreturn]] void childThrew(const char* cause) {
    (void)!::write(STDERR_FILENO, "\n", 1);
    (void)!::write(STDERR_FILENO, cause, std::strlen(cause));
    (void)!::write(STDERR_FILENO, "\n", 1);
    ::_exit(kChildThrew);
}

/// In the child: runs `produce`, sends what it made on `fd`, and exits.
[[noreturn]] void answerAndExit(const std::function<std::string()>& produce, int fd) {
    // An exception (std::bad_alloc, std::length_error, …) would end the child in std::terminate, which the parent
    // could only report as a crash: its cause goes back instead.
    std::string bytes;
    try {
        bytes = produce();
    } catch (const std::exception& e) {
        childThrew(e.what());
    } catch (...) {
        childThrew("an exception that is not a std::exception");
    }
    for (std::size_t done = 0; done < bytes.size();) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n <= 0)
            ::_exit(kChildCouldNotSend);
        done += std::size_t(n);
    }
    ::_exit(0);
}

/// Keeps what the child printed to its first and last 64 KiB: the first line says why assimp aborted, the last
/// why `produce` threw, and a child that prints without end must not fill this process's memory.
void keepEnds(std::string& text) {
    constexpr std::size_t kEnd = 64 << 10;
    if (text.size() > 3 * kEnd)
        text.erase(kEnd, text.size() - 2 * kEnd);
}

/// The first line of what the child printed (assimp's ai_assert before an abort), or its last (the cause
/// childThrew() printed after whatever came before), at most 200 characters.
std::string childSaid(const std::string& errors, bool last) {
    std::string text = errors;
    while (!text.empty() && text.back() == '\n')
        text.pop_back();
    const std::size_t from = last ? (text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1) : 0;
    const std::size_t to = std::min(text.find('\n', from), text.size());
    return text.substr(from, std::min<std::size_t>(to - from, 200));
}

/// A child's pipes, seen from the parent: its answer, what it printed, its progress beats, and (the program)
/// its request, which the parent writes.
struct ChildPipes {
    int answer = -1, errors = -1, beats = -1, request = -1;
};

/// Watches a started child until it ends: reads its answer, what it prints and its beats, writes `request` to
/// it, and stops it when it shows no sign of life (its answer's bytes, its beats) for the idle window or runs
/// past the overall bound. Every pipe at once: a child that fills one while the parent waits on another would
/// hang. A long import that keeps reporting progress (an animation's samples) is not stopped for being long:
/// 3,601 samples of the rigged guppy took 6 s under ASan here, and were stopped on a slower machine when every
/// import was stopped 10 s after it started. Closes the pipes and reaps the child.
Result<std::string> supervise(pid_t child, ChildPipes pipes, const std::string& request, const std::filesystem::path& path,
                              const std::string& name, double idleSeconds) {
    std::error_code sizeError;
    const auto megabytes = std::filesystem::file_size(path, sizeError) >> 20;
    const auto perFile = std::chrono::milliseconds(100 * megabytes);
    const auto idle = std::chrono::milliseconds(std::int64_t(idleSeconds * 1000)) + perFile;
    const auto started = std::chrono::steady_clock::now();
    const auto mostUntil = started + std::chrono::milliseconds(std::int64_t(kImportMostSeconds * 1000)) + perFile;
    auto quietUntil = started + idle;
    std::string bytes, errors;
    std::size_t written = 0;
    if (pipes.request >= 0 && request.empty()) {
        ::close(pipes.request);
        pipes.request = -1;
    }
    char chunk[1 << 16];
    pollfd open[4] = {{pipes.answer, POLLIN, 0}, {pipes.errors, POLLIN, 0}, {pipes.beats, POLLIN, 0},
                      {pipes.request, POLLOUT, 0}};
    enum class Stopped { No, Idle, TooLong } stopped = Stopped::No;
    while (open[0].fd >= 0 || open[1].fd >= 0 || open[2].fd >= 0) {
        const auto until = std::min(quietUntil, mostUntil);
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
        const int ready = left.count() > 0 ? ::poll(open, 4, int(left.count())) : 0;
        if (ready == 0) {
            stopped = until == mostUntil ? Stopped::TooLong : Stopped::Idle;
            ::kill(child, SIGKILL);
            break;
        }
        if (ready < 0) {
            if (errno == EINTR)
                continue;
            break;
        }
        if (open[3].fd >= 0 && open[3].revents != 0) {
            // send(MSG_NOSIGNAL) on the request's socket: a child that died must not take this process with SIGPIPE.
            const ssize_t n = (open[3].revents & POLLOUT)
                                  ? ::send(open[3].fd, request.data() + written, request.size() - written, MSG_NOSIGNAL)
                                  : -1;
            if (n > 0)
                written += std::size_t(n);
            if (written == request.size() || (n < 0 && errno != EINTR && errno != EAGAIN)) {
                ::close(open[3].fd);  // all of it, or a child that no longer reads
                open[3].fd = -1;
            }
        }
        for (int i = 0; i < 3; ++i) {
            if (open[i].fd < 0 || open[i].revents == 0)
                continue;
            const ssize_t n = ::read(open[i].fd, chunk, sizeof chunk);
            if (n > 0) {
                if (i == 0)
                    bytes.append(chunk, std::size_t(n));
                if (i == 1) {
                    errors.append(chunk, std::size_t(n));
                    keepEnds(errors);
                }
                // Its answer and its beats are progress; what it prints is not (assimp looping on a malformed
                // file may warn each time round).
                if (i != 1)
                    quietUntil = std::chrono::steady_clock::now() + idle;
            } else if (n == 0 || errno != EINTR) {
                ::close(open[i].fd);
                open[i].fd = -1;
            }
        }
    }
    for (const pollfd& p : open)
        if (p.fd >= 0)
            ::close(p.fd);
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    auto seconds = [](std::chrono::milliseconds ms) { return std::to_string((ms.count() + 500) / 1000); };
    if (stopped == Stopped::Idle)
        return Status::error("cannot read mesh " + name + ": the importer (assimp) showed no progress for " +
                             seconds(idle) + " s and was stopped");
    if (stopped == Stopped::TooLong)
        return Status::error("cannot read mesh " + name + ": the importer (assimp) did not finish within " +
                             seconds(std::chrono::duration_cast<std::chrono::milliseconds>(mostUntil - started)) +
                             " s and was stopped");
    if (WIFSIGNALED(status)) {
        const std::string said = childSaid(errors, false);
        return Status::error("cannot read mesh " + name + ": the importer (assimp) crashed on it (signal " +
                             std::to_string(WTERMSIG(status)) + (said.empty() ? "" : ": " + said) +
                             "); the file is corrupt or in a form assimp cannot read");
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == kChildThrew)
        return Status::error("cannot read mesh " + name + ": the importer failed: " + childSaid(errors, true));
    if (WIFEXITED(status) && WEXITSTATUS(status) == kChildCouldNotSend)
        return Status::error("cannot read mesh " + name + ": the importer could not send back what it read (" +
                             std::to_string(bytes.size()) + " bytes arrived)");
    if (WIFEXITED(status) && WEXITSTATUS(status) == kChildBadRequest)
        return Status::error("cannot read mesh " + name + ": the importer program did not understand its request (" +
                             childSaid(errors, true) + "); it is not the one this program was built with");
    if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
        const std::string said = childSaid(errors, false);
        return Status::error("cannot read mesh " + name + ": the importer (assimp) failed on it (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                             (said.empty() ? "" : ": " + said) + "); the file is corrupt or in a form assimp cannot read");
    }
    return bytes;
}

void closeAll(std::initializer_list<int> fds) {
    for (int fd : fds)
        if (fd >= 0)
            ::close(fd);
}

/// Three pipes (answer, errors, beats), close-on-exec; false, with none open, where one cannot be made.
bool makePipes(int (&answer)[2], int (&errors)[2], int (&beats)[2]) {
    if (::pipe2(answer, O_CLOEXEC) != 0)
        return false;
    if (::pipe2(errors, O_CLOEXEC) != 0) {
        closeAll({answer[0], answer[1]});
        return false;
    }
    if (::pipe2(beats, O_CLOEXEC) != 0) {
        closeAll({answer[0], answer[1], errors[0], errors[1]});
        return false;
    }
    return true;
}

}  // namespace

void reportImportProgress() {
    if (progressFd < 0)
        return;
    // At most ten a second: the parent only needs a sign of life well within its idle window.
    static std::chrono::steady_clock::time_point last;
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(100))
        return;
    last = now;
    const char beat = 1;
    (void)!::write(progressFd, &beat, 1);
}

Result<std::string> runIsolated(const std::filesystem::path& path, const std::string& name,
                                const std::function<std::string()>& produce, double idleSeconds) {
    int fds[2], errs[2], beats[2];
    if (!makePipes(fds, errs, beats))
        return produce();  // no pipe: read in this process rather than not at all
    std::fflush(nullptr);
    const pid_t child = ::fork();
    if (child < 0) {
        closeAll({fds[0], fds[1], errs[0], errs[1], beats[0], beats[1]});
        return produce();
    }
    if (child == 0) {
        // A crash in the child must end the child and nothing else: handlers inherited from the parent
        // (a crash reporter; under the fuzzer, libFuzzer's, which would file the child's crash as the
        // parent's finding) are put back to the default, so the parent sees the signal and reports it.
        for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT})
            ::signal(sig, SIG_DFL);
        // What assimp prints before it aborts ("ai_assert failure in …") goes to the parent's message.
        ::dup2(errs[1], STDERR_FILENO);
        closeAll({fds[0], errs[0], beats[0]});
        progressFd = beats[1];
        answerAndExit(produce, fds[1]);
    }
    closeAll({fds[1], errs[1], beats[1]});
    return supervise(child, {fds[0], errs[0], beats[0], -1}, std::string(), path, name, idleSeconds);
}

std::filesystem::path importerProgram() {
    static const std::filesystem::path program = [] {
        std::error_code ec;
        const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
        const std::filesystem::path beside = ec ? std::filesystem::path() : self.parent_path() / kImporterProgramName;
        return !beside.empty() && ::access(beside.c_str(), X_OK) == 0 ? beside : std::filesystem::path();
    }();
    return program;
}

Result<std::string> runImport(const ImportRequest& request, const std::string& name) {
    const std::filesystem::path& path = request.paths.front();
    const std::filesystem::path program = importerProgram();
    if (program.empty())
        return runIsolated(path, name, [&] { return answerImportRequest(request); });
    int fds[2], errs[2], beats[2], input[2];  // input: a socket pair, the child's stdin
    if (!makePipes(fds, errs, beats))
        return answerImportRequest(request);
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, input) != 0) {
        closeAll({fds[0], fds[1], errs[0], errs[1], beats[0], beats[1]});
        return answerImportRequest(request);
    }
    // The child's stdin is its request, stdout its answer, stderr what it prints, fd 3 its beats; 3 last, so that
    // a pipe end that happens to be fd 3 has been moved before it is replaced.
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, input[0], STDIN_FILENO);
    posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, errs[1], STDERR_FILENO);
    posix_spawn_file_actions_adddup2(&actions, beats[1], kProgramProgressFd);
    std::string programName = program.string();
    char* argv[] = {programName.data(), nullptr};
    pid_t child = -1;
    const int spawned = ::posix_spawn(&child, program.c_str(), &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    closeAll({fds[1], errs[1], beats[1], input[0]});
    if (spawned != 0) {
        closeAll({fds[0], errs[0], beats[0], input[1]});
        return runIsolated(path, name, [&] { return answerImportRequest(request); });
    }
    // The request goes in as the child reads it, never blocking the watch over its other pipes.
    ::fcntl(input[1], F_SETFL, ::fcntl(input[1], F_GETFL) | O_NONBLOCK);
    return supervise(child, {fds[0], errs[0], beats[0], input[1]}, encodeImportRequest(request), path, name,
                     kImportIdleSeconds);
}

int importerMain() {
    std::string request;
    char chunk[1 << 16];
    for (ssize_t n; (n = ::read(STDIN_FILENO, chunk, sizeof chunk)) != 0;) {
        if (n < 0) {
            if (errno == EINTR)
                continue;
            std::fputs("cannot read the request\n", stderr);
            return kChildBadRequest;
        }
        request.append(chunk, std::size_t(n));
    }
    auto decoded = decodeImportRequest(request);
    if (!decoded) {
        std::fputs("its request did not decode\n", stderr);
        return kChildBadRequest;
    }
    progressFd = kProgramProgressFd;
    answerAndExit([&] { return answerImportRequest(*decoded); }, STDOUT_FILENO);
}

}  // namespace softtouch::io
