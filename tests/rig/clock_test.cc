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

// The one wait the rig does on the OS clock: it must not return before its deadline (how much later
// it returns is the OS's, and the runner measures it; no upper bound is asserted here).
TEST(SteadyClockTest, SleepUntilReturnsNoEarlierThanTheDeadline) {
  const SteadyClock clock;
  const std::int64_t deadline_ns = clock.NowNs() + 200'000;

  clock.SleepUntilNs(deadline_ns);

  EXPECT_GE(clock.NowNs(), deadline_ns);
}

TEST(FakePacingClockTest, SleepJumpsToTheDeadline) {
  const FakePacingClock clock(1'000);

  clock.SleepUntilNs(5'000);

  EXPECT_EQ(clock.NowNs(), 5'000);
  EXPECT_EQ(clock.sleeps(), 1u);
}

TEST(FakePacingClockTest, SleepIntoThePastDoesNotWaitOrGoBack) {
  const FakePacingClock clock(9'000);

  clock.SleepUntilNs(5'000);
  clock.SleepUntilNs(9'000);

  EXPECT_EQ(clock.NowNs(), 9'000);
  EXPECT_EQ(clock.sleeps(), 0u);
}

TEST(FakePacingClockTest, WorkAdvancesTime) {
  const FakePacingClock clock;
  const PacingClock& pacing = clock;

  clock.AdvanceNs(250);
  clock.AdvanceNs(750);

  EXPECT_EQ(pacing.NowNs(), 1'000);
}

TEST(FakePacingClockDeathTest, NegativeWorkAborts) {
  const FakePacingClock clock;

  EXPECT_DEATH(clock.AdvanceNs(-1), "backwards");
}

}  // namespace
}  // namespace hilrig::rig
