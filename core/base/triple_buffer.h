#pragma once
/// The newest of a stream of values, passed from one writer thread to one reader thread without a lock
/// and without copying under contention: the writer fills its back buffer and publishes it (swapping it
/// with the middle, marked fresh); the reader, when the middle is fresh, swaps it with its front. Neither
/// ever waits, and the reader always sees a whole value: the last one published before it looked. The
/// haptic loop's snapshots leave the 1 kHz thread through one (core/haptics/haptic_loop.h).

#include <array>
#include <atomic>

namespace softtouch {

template <typename T>
class TripleBuffer {
public:
    /// All three buffers (size them once, before the threads start).
    std::array<T, 3>& buffers() { return m_buffers; }

    /// Writer: the buffer to fill next.
    T& back() { return m_buffers[m_back]; }
    /// Writer: makes back() the newest value; back() is then another buffer.
    void publish() { m_back = m_middle.exchange(m_back | kFresh, std::memory_order_acq_rel) & ~kFresh; }

    /// Reader: takes the newest value as front() when one was published since the last take; false
    /// (front() unchanged) otherwise.
    bool take() {
        if (!(m_middle.load(std::memory_order_relaxed) & kFresh))
            return false;
        m_front = m_middle.exchange(m_front, std::memory_order_acq_rel) & ~kFresh;
        return true;
    }
    /// Reader: the value last taken.
    const T& front() const { return m_buffers[m_front]; }

private:
    static constexpr unsigned kFresh = 4;  ///< Set in m_middle when it holds a value not yet taken.
    std::array<T, 3> m_buffers{};
    unsigned m_back = 0;                    ///< Writer's.
    alignas(64) std::atomic<unsigned> m_middle{1};
    unsigned m_front = 2;                   ///< Reader's.
};

}  // namespace softtouch
