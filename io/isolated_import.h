#pragma once
/// Reading an outside file in a child process, and the bytes the child sends back. Debian's assimp 5.2
/// aborts, or reads past its buffers, on some corrupt files; in a child that crash becomes an error
/// message instead of taking the editor, and the user's unsaved work, with it (io/mesh_import.cpp).

#include "core/result.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace softtouch::io {

/// Runs `produce` in a child process (10 s, plus 0.1 s per MiB of `path`, at most) and returns the bytes it
/// made. A crash, a hang or a failure of the child is an error naming `name` ("cannot read mesh NAME: …").
/// Where no child can be started, `produce` runs in this process.
Result<std::string> runIsolated(const std::filesystem::path& path, const std::string& name,
                                const std::function<std::string()>& produce);

/// Appends a value's bytes.
template <typename T>
void put(std::string& out, const T& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}
template <typename T>
void putVector(std::string& out, const std::vector<T>& values) {
    put(out, std::uint64_t(values.size()));
    out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

/// Reads back what put() and putVector() wrote; every read says whether the bytes held it.
class Decoder {
public:
    explicit Decoder(const std::string& bytes) : m_bytes(bytes) {}
    template <typename T>
    bool get(T& value) {
        if (m_bytes.size() - m_at < sizeof value)
            return false;
        std::memcpy(&value, m_bytes.data() + m_at, sizeof value);
        m_at += sizeof value;
        return true;
    }
    bool getBytes(std::string& out) {
        std::uint64_t n = 0;
        if (!get(n) || m_bytes.size() - m_at < n)
            return false;
        out.assign(m_bytes.data() + m_at, std::size_t(n));
        m_at += std::size_t(n);
        return true;
    }
    template <typename T>
    bool getVector(std::vector<T>& values) {
        std::uint64_t n = 0;
        if (!get(n) || (m_bytes.size() - m_at) / sizeof(T) < n)
            return false;
        values.resize(std::size_t(n));
        std::memcpy(static_cast<void*>(values.data()), m_bytes.data() + m_at, std::size_t(n) * sizeof(T));
        m_at += std::size_t(n) * sizeof(T);
        return true;
    }

private:
    const std::string& m_bytes;
    std::size_t m_at = 0;
};


}  // namespace softtouch::io
