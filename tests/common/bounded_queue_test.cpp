// The bounded queue's two overflow policies, its blocking and timed pops, its wake
// and its shutdown.
#include "sgslam/common/bounded_queue.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace sgslam {
namespace {

TEST(BoundedQueue, DropOldestKeepsTheNewestAndCountsTheDropped) {
  BoundedQueue<int> q(2, Overflow::kDropOldest);
  EXPECT_FALSE(q.Push(1).dropped);
  EXPECT_FALSE(q.Push(2).dropped);
  const auto pushed = q.Push(3);  // full: 1 goes
  EXPECT_TRUE(pushed.accepted);
  ASSERT_TRUE(pushed.dropped);
  EXPECT_EQ(*pushed.dropped, 1);
  EXPECT_EQ(q.dropped(), 1u);
  EXPECT_EQ(q.size(), 2u);
  EXPECT_EQ(q.Pop(), 2);
  EXPECT_EQ(q.Pop(), 3);
}

TEST(BoundedQueue, BlockWaitsForRoomAndKeepsEveryItem) {
  BoundedQueue<int> q(1, Overflow::kBlock);
  std::vector<int> got;
  std::thread consumer([&] {
    while (auto v = q.Pop()) got.push_back(*v);
  });
  for (int i = 0; i < 100; ++i) EXPECT_TRUE(q.Push(i).accepted);
  q.Shutdown();  // the consumer drains what is queued, then Pop gives nullopt
  consumer.join();
  ASSERT_EQ(got.size(), 100u);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(got[i], i);
  EXPECT_EQ(q.dropped(), 0u);
}

TEST(BoundedQueue, ShutdownWakesABlockedProducerAndConsumer) {
  BoundedQueue<int> full(1, Overflow::kBlock), empty(1);
  full.Push(0);
  bool producer_done = false;
  std::optional<int> popped = 7;
  std::thread producer([&] { producer_done = !full.Push(1).accepted; });
  std::thread consumer([&] { popped = empty.Pop(); });
  full.Shutdown();
  empty.Shutdown();
  producer.join();
  consumer.join();
  EXPECT_TRUE(producer_done) << "a push after shutdown is refused";
  EXPECT_FALSE(popped);
  EXPECT_EQ(full.Pop(), 0) << "what was queued can still be taken";
}

TEST(BoundedQueue, ShutdownAndClearTakesEverythingOut) {
  BoundedQueue<int> q(3, Overflow::kDropOldest);
  q.Push(1);
  q.Push(2);
  const auto items = q.ShutdownAndClear();
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items.front(), 1);
  EXPECT_EQ(q.size(), 0u);
  EXPECT_FALSE(q.Pop()) << "nothing is handed out after it";
  EXPECT_FALSE(q.Push(3).accepted);
}

// The semantic map's wake-up: never pushes an item out of a full drop-oldest queue.
TEST(BoundedQueue, PushIfEmptyNeverDrops) {
  BoundedQueue<int> q(1, Overflow::kDropOldest);
  EXPECT_TRUE(q.PushIfEmpty(1));
  EXPECT_FALSE(q.PushIfEmpty(2)) << "one waits: it is served first";
  EXPECT_EQ(q.dropped(), 0u);
  EXPECT_EQ(q.Pop(), 1);
  q.Shutdown();
  EXPECT_FALSE(q.PushIfEmpty(3));
}

// The ROS node's frames: the newest kept, a timed pop for a consumer with other work.
TEST(BoundedQueue, PopForTimesOutIsWokenAndDrainsAfterShutdown) {
  BoundedQueue<int> q(2, Overflow::kDropOldest);
  for (int i = 0; i < 5; ++i) q.Push(i);
  EXPECT_EQ(q.dropped(), 3u);
  EXPECT_EQ(q.PopFor(std::chrono::milliseconds(0)), 3);
  EXPECT_EQ(q.PopFor(std::chrono::milliseconds(0)), 4);
  EXPECT_FALSE(q.PopFor(std::chrono::milliseconds(1)));  // timed out
  EXPECT_FALSE(q.shut_down());

  std::thread waker([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    q.Wake();
  });
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(q.PopFor(std::chrono::seconds(60)));  // woken long before the minute
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
  waker.join();

  q.Push(9);
  q.Shutdown();
  EXPECT_FALSE(q.Push(10).accepted);
  EXPECT_EQ(q.PopFor(std::chrono::milliseconds(0)), 9);
  EXPECT_FALSE(q.PopFor(std::chrono::milliseconds(0)));
  EXPECT_TRUE(q.shut_down());
}

}  // namespace
}  // namespace sgslam
