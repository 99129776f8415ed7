// The loop's two lock-free hand-offs, exercised by two real threads: the SPSC command queue delivers
// every item once and in order; the triple buffer only ever shows whole, published, newer values.
#include <gtest/gtest.h>

#include <array>
#include <thread>

#include "hapticut/common/spsc_queue.h"
#include "hapticut/common/triple_buffer.h"

namespace hapticut {
namespace {

TEST(SpscQueue, DeliversEveryItemOnceAndInOrderBetweenTwoThreads) {
    SpscQueue<long, 64> queue;
    constexpr long kItems = 200'000;
    std::thread producer([&] {
        for (long i = 1; i <= kItems; ++i)
            while (!queue.push(i)) std::this_thread::yield();  // full: the consumer catches up
    });
    long expected = 1, sum = 0;
    while (expected <= kItems) {
        if (const auto item = queue.pop()) {
            ASSERT_EQ(*item, expected) << "out of order or duplicated";
            sum += *item;
            ++expected;
        }
    }
    producer.join();
    EXPECT_EQ(sum, kItems * (kItems + 1) / 2);
    EXPECT_FALSE(queue.pop()) << "nothing left over";
}

TEST(SpscQueue, RefusesWhenFullAndTakesAgainOnceEmptied) {
    SpscQueue<int, 4> queue;
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(queue.push(i));
    EXPECT_FALSE(queue.push(4));
    EXPECT_EQ(queue.pop(), 0);
    EXPECT_TRUE(queue.push(4));
    for (int i = 1; i <= 4; ++i) EXPECT_EQ(queue.pop(), i);
    EXPECT_FALSE(queue.pop());
}

/// A value whose parts are written one by one: a torn read would show parts that disagree.
struct Frame {
    long id = 0;
    std::array<long, 64> copies{};
};

TEST(TripleBuffer, TheReaderSeesWholePublishedFramesThatNeverGoBack) {
    TripleBuffer<Frame> buffer;
    constexpr long kFrames = 100'000;
    std::thread writer([&] {
        for (long id = 1; id <= kFrames; ++id) {
            Frame& f = buffer.writeSlot();
            f.id = id;
            f.copies.fill(id);
            buffer.publish();
        }
    });
    long last = 0, reads = 0;
    while (last < kFrames) {
        const Frame& f = buffer.readLatest();
        for (long c : f.copies) ASSERT_EQ(c, f.id) << "a frame torn between two writes";
        ASSERT_GE(f.id, last) << "an older frame after a newer one";
        last = f.id;
        ++reads;
    }
    writer.join();
    EXPECT_EQ(buffer.readLatest().id, kFrames) << "the newest frame is the one left to read";
    EXPECT_GT(reads, 0);
}

TEST(TripleBuffer, ReadingTwiceWithoutAPublishGivesTheSameFrame) {
    TripleBuffer<Frame> buffer;
    buffer.writeSlot().id = 7;
    buffer.publish();
    EXPECT_EQ(buffer.readLatest().id, 7);
    EXPECT_EQ(buffer.readLatest().id, 7);
    buffer.writeSlot().id = 8;  // written but not yet published
    EXPECT_EQ(buffer.readLatest().id, 7);
}

}  // namespace
}  // namespace hapticut
