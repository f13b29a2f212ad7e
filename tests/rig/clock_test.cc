#include "rig/clock.h"

#include <gtest/gtest.h>

namespace hilrig::rig {
namespace {

TEST(SimClockTest, StartsAtGivenTime) {
  const SimClock clock(5'000);

  EXPECT_EQ(clock.NowNs(), 5'000);
}

TEST(SimClockTest, AdvancesOnlyWhenTold) {
  SimClock clock;

  clock.AdvanceNs(1'000);
  clock.AdvanceNs(250);

  EXPECT_EQ(clock.NowNs(), 1'250);
}

TEST(SimClockTest, WorksThroughClockInterface) {
  SimClock sim(7);
  const Clock& clock = sim;

  sim.AdvanceNs(3);

  EXPECT_EQ(clock.NowNs(), 10);
}

TEST(SimClockDeathTest, NegativeStepAborts) {
  SimClock clock;

  EXPECT_DEATH(clock.AdvanceNs(-1), "backwards");
}

TEST(SteadyClockTest, StartsNearZeroAndNeverDecreases) {
  const SteadyClock clock;

  const std::int64_t first_ns = clock.NowNs();
  const std::int64_t second_ns = clock.NowNs();

  EXPECT_GE(first_ns, 0);
  EXPECT_LT(first_ns, 1'000'000'000);  // construction was moments ago, not since boot
  EXPECT_GE(second_ns, first_ns);
}

}  // namespace
}  // namespace hilrig::rig
