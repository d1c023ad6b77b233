#pragma once
/// A bounded queue between exactly one producer thread and one consumer thread, lock-free and
/// allocation-free: the haptic loop's commands (core/haptics/haptic_loop.h) travel through one. Each side
/// writes only its own index and reads the other's with acquire/release ordering, so an item is fully
/// written before the consumer sees it and fully used before the producer reuses its slot.

#include <array>
#include <atomic>
#include <cstddef>

namespace softtouch {

/// Holds up to Capacity − 1 items (one slot stays empty to tell full from empty).
template <typename T, std::size_t Capacity>
class SpscRing {
    static_assert(Capacity >= 2, "a ring needs two slots");

public:
    /// Producer: appends `item`; false (nothing changed) when the ring is full.
    bool push(const T& item) {
        const std::size_t tail = m_tail.load(std::memory_order_relaxed);
        const std::size_t next = (tail + 1) % Capacity;
        if (next == m_head.load(std::memory_order_acquire))
            return false;
        m_items[tail] = item;
        m_tail.store(next, std::memory_order_release);
        return true;
    }

    /// Consumer: the oldest item, or nullptr when empty. It stays valid (the producer cannot reuse its
    /// slot) until pop().
    const T* front() const {
        const std::size_t head = m_head.load(std::memory_order_relaxed);
        return head == m_tail.load(std::memory_order_acquire) ? nullptr : &m_items[head];
    }

    /// Consumer: releases the item front() returned. Only after a non-null front().
    void pop() { m_head.store((m_head.load(std::memory_order_relaxed) + 1) % Capacity, std::memory_order_release); }

    /// Items a push can still add (exact on either side's own thread when the other is idle).
    std::size_t freeSlots() const {
        const std::size_t head = m_head.load(std::memory_order_acquire), tail = m_tail.load(std::memory_order_acquire);
        return (head + Capacity - tail - 1) % Capacity;
    }

private:
    std::array<T, Capacity> m_items{};
    alignas(64) std::atomic<std::size_t> m_head{0};  ///< Next to read; written by the consumer.
    alignas(64) std::atomic<std::size_t> m_tail{0};  ///< Next to write; written by the producer.
};

}  // namespace softtouch
