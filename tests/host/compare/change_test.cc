// A margin's change graded against the tolerance: more room is better, a shrink within the stated
// fraction of the base's margin is tolerated, beyond it is worse, and NaN is never better.
#include "host/compare/change.h"

#include <gtest/gtest.h>

#include <limits>

namespace hilrig::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(MarginChangeTest, GradesTheShrinkAgainstAFractionOfTheBaseMargin) {
  EXPECT_EQ(MarginChange(0.1, 0.1, 0.1), proto::SAME);
  EXPECT_EQ(MarginChange(0.1, 0.2, 0.1), proto::BETTER);
  EXPECT_EQ(MarginChange(0.1, 0.095, 0.1), proto::WORSE_WITHIN_TOLERANCE);
  EXPECT_EQ(MarginChange(0.1, 0.08, 0.1), proto::WORSE);
  EXPECT_EQ(MarginChange(0.1, 0.09999, 0), proto::WORSE);
  // A negative base margin (already outside) scales by its size: -0.1 may go to -0.11.
  EXPECT_EQ(MarginChange(-0.1, -0.105, 0.1), proto::WORSE_WITHIN_TOLERANCE);
  EXPECT_EQ(MarginChange(-0.1, -0.2, 0.1), proto::WORSE);
  // A zero margin leaves no room to tolerate.
  EXPECT_EQ(MarginChange(0, -1e-12, 0.5), proto::WORSE);
}

TEST(MarginChangeTest, ANaNMarginIsNeverBetter) {
  EXPECT_EQ(MarginChange(0.1, kNaN, 10), proto::WORSE);
  EXPECT_EQ(MarginChange(kNaN, 0.1, 0.1), proto::BETTER);
  EXPECT_EQ(MarginChange(kNaN, kNaN, 0.1), proto::SAME);
}

TEST(CountsAsWorseTest, OnlyARegressionOrALossCounts) {
  EXPECT_TRUE(CountsAsWorse(proto::WORSE));
  EXPECT_TRUE(CountsAsWorse(proto::ONLY_IN_BASE));
  for (const auto change : {proto::SAME, proto::BETTER, proto::WORSE_WITHIN_TOLERANCE,
                            proto::ONLY_IN_CANDIDATE, proto::CHANGE_UNSPECIFIED}) {
    EXPECT_FALSE(CountsAsWorse(change)) << ChangeText(change);
  }
}

}  // namespace
}  // namespace hilrig::host
