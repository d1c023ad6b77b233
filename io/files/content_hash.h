#pragma once
/// FNV-1a, 64 bit: the content key of what is made from files (a batch job's stamp, a study's cached
/// reference), for change detection, not for security (the inputs are the user's own).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace softtouch::io {

struct ContentHash {
    std::uint64_t value = 0xcbf29ce484222325ull;
    void add(const void* data, std::size_t size) {
        const auto* bytes = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < size; ++i)
            value = (value ^ bytes[i]) * 0x100000001b3ull;
    }
    /// The text and a NUL after it, so that "ab" + "c" and "a" + "bc" differ.
    void add(const std::string& text) {
        add(text.data(), text.size());
        add("\0", 1);
    }
    /// The element count, then the elements' bytes.
    template <typename T>
    void add(const std::vector<T>& items) {
        const std::uint64_t count = items.size();
        add(&count, sizeof count);
        add(items.data(), items.size() * sizeof(T));
    }
};

}  // namespace softtouch::io
