#include "event_queue.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "test_systems.hpp"

namespace carom {
namespace {

TEST(EventQueue, StartsWithNoEventForAnyone) {
  EventQueue queue(3);
  EXPECT_EQ(queue.top_key().time, kNever);
  EXPECT_EQ(queue.top(), 0u);
}

TEST(EventQueue, ReplacingAnEventMovesItBothWays) {
  EventQueue queue(4);
  queue.update(2, {5.0, 0});
  queue.update(3, {1.0, 0});
  EXPECT_EQ(queue.top(), 3u);
  queue.update(3, {9.0, 0});  // later: sinks
  EXPECT_EQ(queue.top(), 2u);
  queue.update(1, {0.5, 0});  // earlier: rises
  EXPECT_EQ(queue.top(), 1u);
  EXPECT_EQ(queue.key(3).time, 9.0);
}

TEST(EventQueue, EqualKeysGoToTheLowerParticle) {
  EventQueue queue(5);
  for (std::uint32_t i : {4u, 1u, 3u}) queue.update(i, {2.0, 7});
  EXPECT_EQ(queue.top(), 1u);
  queue.update(1, {3.0, 0});
  EXPECT_EQ(queue.top(), 3u);
}

TEST(EventQueue, AgreesWithASortedListUnderRandomUpdates) {
  pcg32 rng(5);
  const std::uint32_t n = 257;
  EventQueue queue(n);
  std::vector<EventKey> keys(n, EventQueue::kNone);
  for (int step = 0; step < 20000; ++step) {
    const std::uint32_t i = rng() % n;
    keys[i] = {static_cast<double>(rng() % 50), rng() % 3};
    queue.update(i, keys[i]);
    std::uint32_t best = 0;
    for (std::uint32_t j = 1; j < n; ++j) {
      if (keys[j] < keys[best]) best = j;
    }
    ASSERT_EQ(queue.top(), best) << "step " << step;
    ASSERT_EQ(queue.top_key(), keys[best]);
  }
}

}  // namespace
}  // namespace carom
