#include "event_queue.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "engine/event_calendar.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

// The heap and the calendar must order events identically: the engine's results depend on it.
template <class Queue>
class EventQueues : public ::testing::Test {};
using QueueTypes = ::testing::Types<EventQueue, EventCalendar>;
TYPED_TEST_SUITE(EventQueues, QueueTypes);

TYPED_TEST(EventQueues, StartsWithNoEventForAnyone) {
  TypeParam queue(3);
  EXPECT_EQ(queue.top_key().time, kNever);
  EXPECT_EQ(queue.top(), 0u);
}

TYPED_TEST(EventQueues, ReplacingAnEventMovesItBothWays) {
  TypeParam queue(4);
  queue.update(2, {5.0, 0});
  queue.update(3, {1.0, 0});
  EXPECT_EQ(queue.top(), 3u);
  queue.update(3, {9.0, 0});  // later: sinks
  EXPECT_EQ(queue.top(), 2u);
  queue.update(1, {0.5, 0});  // earlier: rises
  EXPECT_EQ(queue.top(), 1u);
  EXPECT_EQ(queue.key(3).time, 9.0);
}

TYPED_TEST(EventQueues, EqualKeysGoToTheLowerParticle) {
  TypeParam queue(5);
  for (std::uint32_t i : {4u, 1u, 3u}) queue.update(i, {2.0, 7});
  EXPECT_EQ(queue.top(), 1u);
  queue.update(1, {3.0, 0});
  EXPECT_EQ(queue.top(), 3u);
}

TYPED_TEST(EventQueues, AgreesWithASortedListUnderRandomUpdates) {
  pcg32 rng(5);
  const std::uint32_t n = 257;
  TypeParam queue(n);
  std::vector<EventKey> keys(n, kNoEvent);
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

// The engine's pattern: the earliest event is replaced by a later one, now and then by one due at
// once or in the far future, or by none; many years of the calendar go by.
TYPED_TEST(EventQueues, AgreesWithASortedListAsTimeGoesOn) {
  pcg32 rng(7);
  const std::uint32_t n = 300;
  TypeParam queue(n);
  std::vector<EventKey> keys(n, kNoEvent);
  const auto uniform = [&] { return static_cast<double>(rng()) / 4294967296.0; };
  for (std::uint32_t i = 0; i < n; ++i) {
    keys[i] = {uniform(), i % 4};
    queue.update(i, keys[i]);
  }
  for (int step = 0; step < 200000; ++step) {
    const std::uint32_t best =
        static_cast<std::uint32_t>(std::min_element(keys.begin(), keys.end()) - keys.begin());
    ASSERT_EQ(queue.top_key(), keys[best]) << "step " << step;
    if (keys[best].time == kNever) break;
    ASSERT_EQ(queue.top(), best) << "step " << step;
    const double now = keys[best].time;
    const std::uint32_t i = rng() % 10 == 0 ? rng() % n : best;
    const std::uint32_t kind = rng() % 1000;
    double later = now + uniform();
    if (kind == 0) later = kNever;
    if (kind == 1) later = now;
    if (kind == 2) later = now + 1e6 * uniform();
    if (kind == 3) later = now + 1e-12 * uniform();
    keys[i] = later == kNever ? kNoEvent : EventKey{later, rng() % 4};
    queue.update(i, keys[i]);
  }
}

TYPED_TEST(EventQueues, EqualTimesAndEmptiness) {
  TypeParam queue(40);
  for (std::uint32_t i = 0; i < 40; ++i) queue.update(i, {1.0, 5});
  for (std::uint32_t i = 0; i < 40; ++i) {
    ASSERT_EQ(queue.top(), i);
    queue.update(i, kNoEvent);
  }
  EXPECT_EQ(queue.top_key(), kNoEvent);
  queue.update(17, {3.0, 1});  // after a year with nothing left, an event starts a new one
  EXPECT_EQ(queue.top(), 17u);
}

// The tag a slot's event was queued with comes back with that slot, wherever the calendar keeps
// the event (its heap, a bucket, the overflow) and across new years; a slot's update replaces it.
TEST(EventCalendar, KeepsEachSlotsTagWithItsEvent) {
  pcg32 rng(11);
  const std::uint32_t n = 200;
  EventCalendar calendar(n);
  std::vector<std::uint32_t> tags(n);
  const auto uniform = [&] { return static_cast<double>(rng()) / 4294967296.0; };
  for (std::uint32_t i = 0; i < n; ++i) {
    tags[i] = rng();
    calendar.update(i, {uniform(), 0}, tags[i]);
  }
  for (int step = 0; step < 50000; ++step) {
    const std::uint32_t i = calendar.top();
    ASSERT_EQ(calendar.tag(i), tags[i]) << "step " << step;
    const std::uint32_t other = rng() % n;
    ASSERT_EQ(calendar.tag(other), tags[other]) << "step " << step;
    tags[i] = rng();
    const double later = calendar.top_key().time + (rng() % 100 == 0 ? 1e4 : 1.0) * uniform();
    calendar.update(i, {later, 0}, tags[i]);
  }
}

}  // namespace
}  // namespace carom
