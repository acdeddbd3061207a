// Replays running at once, per viewer and in all: server/replay_slots.h.
#include "server/replay_slots.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace incise::server {
namespace {

TEST(ReplaySlots, EachViewerHasAShareAndTheServerATotal) {
  ReplaySlots slots(2, 3);
  std::string why;
  auto a1 = slots.take(1, why);
  auto a2 = slots.take(1, why);
  ASSERT_TRUE(a1 && a2);
  EXPECT_FALSE(slots.take(1, why));
  EXPECT_EQ(why, "you have 2 replays open already; close one to open another");
  auto b1 = slots.take(2, why);
  ASSERT_TRUE(b1);
  EXPECT_EQ(slots.in_use(), 3);
  // The total is reached although viewer 3 has opened none.
  EXPECT_FALSE(slots.take(3, why));
  EXPECT_EQ(why, "the server is running its 3 replays at once; try again in a minute");
}

TEST(ReplaySlots, AClosedReplayFreesItsSlot) {
  ReplaySlots slots(1, 2);
  std::string why;
  auto a = slots.take(1, why);
  ASSERT_TRUE(a);
  EXPECT_FALSE(slots.take(1, why));
  a.reset();
  EXPECT_EQ(slots.in_use(), 0);
  auto again = slots.take(1, why);
  EXPECT_TRUE(again);
  EXPECT_EQ(slots.in_use(), 1);
}

TEST(ReplaySlots, TheDefaultTotalFollowsTheMachine) {
  const ReplaySlots slots;
  EXPECT_GE(slots.total(), 4);
  EXPECT_GE(slots.per_user(), 1);
  EXPECT_LE(slots.per_user(), slots.total());
}

}  // namespace
}  // namespace incise::server
