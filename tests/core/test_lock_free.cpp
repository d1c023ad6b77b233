// The two lock-free hand-overs of the haptic loop, on their own: the command ring keeps order and
// never loses or duplicates an item across threads; the triple buffer hands over whole values only,
// never older than one already seen, and the last one published.
#include "core/base/spsc_ring.h"
#include "core/base/triple_buffer.h"

#include <QtTest/QtTest>

#include <array>
#include <cstdint>
#include <thread>

using namespace softtouch;

class TestLockFree : public QObject {
    Q_OBJECT
private slots:
    void ringHoldsCapacityLessOneInOrder();
    void ringCarriesEveryItemOnceAcrossThreads();
    void tripleBufferGivesTheNewestValue();
    void tripleBufferNeverTearsAcrossThreads();
};

void TestLockFree::ringHoldsCapacityLessOneInOrder() {
    SpscRing<int, 8> ring;
    QVERIFY(ring.front() == nullptr);
    QCOMPARE(ring.freeSlots(), std::size_t(7));
    for (int i = 0; i < 7; ++i)
        QVERIFY(ring.push(i));
    QVERIFY(!ring.push(99));  // full: one slot stays empty
    QCOMPARE(ring.freeSlots(), std::size_t(0));
    for (int i = 0; i < 5; ++i) {
        QVERIFY(ring.front() && *ring.front() == i);
        ring.pop();
    }
    for (int i = 7; i < 12; ++i)  // wraps around
        QVERIFY(ring.push(i));
    for (int i = 5; i < 12; ++i) {
        QVERIFY(ring.front() && *ring.front() == i);
        ring.pop();
    }
    QVERIFY(ring.front() == nullptr);
}

void TestLockFree::ringCarriesEveryItemOnceAcrossThreads() {
    struct Item {
        std::uint64_t value;
        std::uint64_t check;  ///< ~value: a half-written item would not match
    };
    SpscRing<Item, 16> ring;  // small, so the producer often finds it full
    constexpr std::uint64_t kCount = 200000;
    std::thread producer([&] {
        for (std::uint64_t v = 1; v <= kCount;)
            if (ring.push(Item{v, ~v}))
                ++v;
            else
                std::this_thread::yield();
    });
    std::uint64_t expected = 1, bad = 0;
    while (expected <= kCount) {
        if (const Item* item = ring.front()) {
            bad += item->value != expected || item->check != ~expected;
            ++expected;
            ring.pop();
        } else {
            std::this_thread::yield();
        }
    }
    producer.join();
    QCOMPARE(bad, std::uint64_t(0));
    QVERIFY(ring.front() == nullptr);
}

void TestLockFree::tripleBufferGivesTheNewestValue() {
    TripleBuffer<int> buffer;
    QVERIFY(!buffer.take());  // nothing published yet
    buffer.back() = 1;
    buffer.publish();
    QVERIFY(buffer.take());
    QCOMPARE(buffer.front(), 1);
    QVERIFY(!buffer.take());  // nothing new: the front stays
    QCOMPARE(buffer.front(), 1);
    for (int v = 2; v <= 4; ++v) {  // three publications before the reader looks
        buffer.back() = v;
        buffer.publish();
    }
    QVERIFY(buffer.take());
    QCOMPARE(buffer.front(), 4);
}

void TestLockFree::tripleBufferNeverTearsAcrossThreads() {
    using Value = std::array<std::uint64_t, 64>;  // every element the same: a mix of two writes would show
    TripleBuffer<Value> buffer;
    constexpr std::uint64_t kLast = 100000;
    std::atomic<bool> done{false};
    std::thread writer([&] {
        for (std::uint64_t v = 1; v <= kLast; ++v) {
            buffer.back().fill(v);
            buffer.publish();
        }
        done.store(true, std::memory_order_release);
    });
    std::uint64_t seen = 0, torn = 0, backwards = 0, takes = 0;
    for (bool finished = false; !finished;) {
        finished = done.load(std::memory_order_acquire);  // one more look after the writer is done
        if (!buffer.take())
            continue;
        ++takes;
        const Value& v = buffer.front();
        for (std::uint64_t x : v)
            torn += x != v[0];
        backwards += v[0] <= seen;
        seen = v[0];
    }
    writer.join();
    QCOMPARE(torn, std::uint64_t(0));
    QCOMPARE(backwards, std::uint64_t(0));
    QCOMPARE(seen, kLast);  // the last value published is the last one seen
    QVERIFY(takes > 0);
}

QTEST_GUILESS_MAIN(TestLockFree)
#include "test_lock_free.moc"
