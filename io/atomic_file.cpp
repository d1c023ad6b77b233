#include "io/atomic_file.h"

#include "io/vertex_cache_internal.h"

#include <atomic>
#include <cerrno>
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

}  // namespace

namespace detail {

std::filesystem::path temporaryPathFor(const std::filesystem::path& target) {
    // The pid keeps two processes apart, the counter two writers (or two staged OBJ frames) of one.
    static std::atomic<std::uint64_t> counter{0};
    std::filesystem::path temporary = target;
    temporary += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
    return temporary;
}

}  // namespace detail

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
