#include "asynevo/pipeline/bounded_queue.hpp"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace asynevo::pipeline {
namespace {

TEST(BoundedQueue, IsFirstInFirstOut) {
  BoundedQueue<int> queue(8);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(queue.push(i));
  EXPECT_EQ(queue.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(queue.pop(), i);
  EXPECT_EQ(queue.size(), 0u);
  EXPECT_EQ(queue.highWater(), 5u);
}

TEST(BoundedQueue, TryPushRefusesWhenFullAndKeepsTheItem) {
  BoundedQueue<std::vector<int>> queue(2);
  std::vector<int> a{1}, b{2}, c{3, 3};
  EXPECT_TRUE(queue.tryPush(a));
  EXPECT_TRUE(queue.tryPush(b));
  EXPECT_FALSE(queue.tryPush(c));
  EXPECT_EQ(c.size(), 2u);  // not moved from
  EXPECT_EQ(queue.pop()->front(), 1);
  EXPECT_TRUE(queue.tryPush(c));
}

TEST(BoundedQueue, CloseDrainsTheRemainingItemsThenEnds) {
  BoundedQueue<int> queue(4);
  queue.push(7);
  queue.push(8);
  queue.close();
  EXPECT_TRUE(queue.closed());
  EXPECT_FALSE(queue.push(9));  // refused after close
  EXPECT_EQ(queue.pop(), 7);
  EXPECT_EQ(queue.pop(), 8);
  EXPECT_EQ(queue.pop(), std::nullopt);
  EXPECT_EQ(queue.pop(), std::nullopt);
}

TEST(BoundedQueue, RejectsZeroCapacity) { EXPECT_THROW(BoundedQueue<int>(0), std::invalid_argument); }

TEST(BoundedQueue, AProducerFasterThanTheCapacityLosesNothingAndKeepsOrder) {
  // Capacity 3 and 20000 items: the producer must block many times; every item arrives once, in order.
  BoundedQueue<int> queue(3);
  constexpr int kItems = 20000;
  std::thread producer([&] {
    for (int i = 0; i < kItems; ++i) ASSERT_TRUE(queue.push(i));
    queue.close();
  });
  int expected = 0;
  while (auto item = queue.pop()) {
    ASSERT_EQ(*item, expected);
    ++expected;
  }
  producer.join();
  EXPECT_EQ(expected, kItems);
  EXPECT_LE(queue.highWater(), 3u);
}

TEST(BoundedQueue, CloseWakesABlockedProducer) {
  BoundedQueue<int> queue(1);
  queue.push(1);
  bool pushed = true;
  std::thread producer([&] { pushed = queue.push(2); });  // blocks: the queue is full
  queue.close();
  producer.join();
  EXPECT_FALSE(pushed);
  EXPECT_EQ(queue.pop(), 1);
  EXPECT_EQ(queue.pop(), std::nullopt);
}

TEST(BoundedQueue, CloseWakesABlockedConsumer) {
  BoundedQueue<int> queue(1);
  std::optional<int> popped = 5;
  std::thread consumer([&] { popped = queue.pop(); });  // blocks: the queue is empty
  queue.close();
  consumer.join();
  EXPECT_EQ(popped, std::nullopt);
}

}  // namespace
}  // namespace asynevo::pipeline
