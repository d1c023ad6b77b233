#include "io/files/input_file.h"

#include <algorithm>
#include <cerrno>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace softtouch::io {
namespace {

const char* kindOf(std::filesystem::file_type type) {
    switch (type) {
    case std::filesystem::file_type::directory: return "a directory";
    case std::filesystem::file_type::fifo: return "a FIFO";
    case std::filesystem::file_type::character: return "a character device";
    case std::filesystem::file_type::block: return "a block device";
    case std::filesystem::file_type::socket: return "a socket";
    default: return "not a regular file";
    }
}

bool isControl(char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }

std::string bytes(std::uintmax_t n) {
    return n >= kMiB ? std::to_string(n / kMiB) + " MiB" : std::to_string(n) + " bytes";
}

}  // namespace

bool hasControlCharacter(std::string_view text) { return std::any_of(text.begin(), text.end(), isControl); }

std::string shownName(std::string text) {
    std::replace_if(text.begin(), text.end(), isControl, '?');
    return text;
}

bool liesInside(const std::filesystem::path& path, const std::filesystem::path& folder) {
    const std::filesystem::path relative = path.lexically_relative(folder);
    return !relative.empty() && relative != "." && *relative.begin() != ".." && !relative.is_absolute();
}

Status checkInputFile(const std::filesystem::path& path, std::uintmax_t maxBytes) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);  // follows links: a link to a file is fine
    if (ec || !std::filesystem::exists(status))
        return Status::error("does not exist");
    if (!std::filesystem::is_regular_file(status))
        return Status::error(std::string("is not a regular file (") + kindOf(status.type()) + ")");
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec)
        return Status::error("cannot be sized: " + ec.message());
    if (size > maxBytes)
        return Status::error("is " + bytes(size) + "; SoftTouch reads at most " + bytes(maxBytes) +
                             " of this kind of file");
    return Status::success();
}

Result<std::string> readInputFile(const std::filesystem::path& path, std::uintmax_t maxBytes) {
    if (Status s = checkInputFile(path, maxBytes); !s)
        return s;
    // The check above looked at a name; what is opened is checked again on its descriptor, so a file
    // swapped for a FIFO in between cannot block the read (O_NONBLOCK: opening a FIFO returns at once).
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return Status::error("cannot be opened");
    struct stat opened {};
    if (::fstat(fd, &opened) != 0 || !S_ISREG(opened.st_mode)) {
        ::close(fd);
        return Status::error("is not a regular file");
    }
    std::string text;
    char chunk[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fd, chunk, sizeof chunk);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            ::close(fd);
            return Status::error("could not be read to its end");
        }
        if (n == 0)
            break;
        text.append(chunk, std::size_t(n));
        if (text.size() > maxBytes) {
            ::close(fd);
            return Status::error("grew past " + bytes(maxBytes) + " while it was read");
        }
    }
    ::close(fd);
    return text;
}

}  // namespace softtouch::io
