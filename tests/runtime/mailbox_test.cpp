#include "runtime/mailbox.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <thread>

namespace ardcell {
namespace {

TEST(Mailbox, FifoAndFullAndEmpty) {
  Mailbox<int, 4> box;
  EXPECT_FALSE(box.try_pop().has_value());
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(box.try_push(i));
  EXPECT_FALSE(box.try_push(99));
  EXPECT_EQ(box.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(box.pop(), i);
  EXPECT_FALSE(box.try_pop().has_value());
}

TEST(Mailbox, TwoThreadsPassEveryMessageInOrder) {
  Mailbox<std::uint32_t, 8> box;
  constexpr std::uint32_t kCount = 50000;
  std::uint64_t sum = 0;
  bool ordered = true;
  std::thread consumer([&] {
    for (std::uint32_t i = 0; i < kCount; ++i) {
      const std::uint32_t v = box.pop();
      ordered = ordered && v == i;
      sum += v;
    }
  });
  for (std::uint32_t i = 0; i < kCount; ++i) box.push(i);
  consumer.join();
  EXPECT_TRUE(ordered);
  EXPECT_EQ(sum, std::uint64_t(kCount) * (kCount - 1) / 2);
}

TEST(Mailbox, EveryWaitGetsTheMessagesOfAProducerThatPauses) {
  // The producer pauses between bursts longer than the waits' spin and yield, so the consumer
  // reaches each of its ways of waiting: spinning, yielding, and asleep on the futex.
  using Wait = Mailbox<int, 4>::Wait;
  for (const Wait wait :
       {Wait{0, std::chrono::microseconds(0)}, Wait{}, Wait{16, std::chrono::microseconds(200)}}) {
    Mailbox<int, 4> box;
    int received = 0;
    bool ordered = true;
    std::thread consumer([&] {
      for (int i = 0; i < 60; ++i) {
        const int v = box.pop(wait);
        ordered = ordered && v == i;
        ++received;
      }
    });
    for (int i = 0; i < 60; ++i) {
      if (i % 3 == 0) std::this_thread::sleep_for(std::chrono::microseconds(50 * (i % 7)));
      box.push(i);
    }
    consumer.join();
    EXPECT_EQ(received, 60) << wait.spins << " spins, " << wait.yield_for.count() << " us";
    EXPECT_TRUE(ordered) << wait.spins << " spins, " << wait.yield_for.count() << " us";
  }
}

}  // namespace
}  // namespace ardcell
