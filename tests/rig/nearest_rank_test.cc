// NearestRank: the rank behind every quantile the rig reports, at the edges and where q·n lands
// on a whole number that binary rounding pushes just past.
#include "rig/nearest_rank.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hilrig::rig {
namespace {

TEST(NearestRankTest, IsTheCeilingOfQTimesNWithinOneAndN) {
  EXPECT_EQ(NearestRank(0.5, 4), 2u);
  EXPECT_EQ(NearestRank(0.26, 4), 2u);
  EXPECT_EQ(NearestRank(0.99, 1000), 990u);
  EXPECT_EQ(NearestRank(0.0, 4), 1u);  // the minimum
  EXPECT_EQ(NearestRank(1.0, 4), 4u);  // the maximum
  EXPECT_EQ(NearestRank(1.0, 1), 1u);
}

TEST(NearestRankTest, AWholeNumberRoundedUpInBinaryIsThatNumber) {
  // 0.07 · 100 and 0.14 · 50 are both 7.000000000000001 in doubles.
  ASSERT_GT(0.07 * 100, 7.0);
  ASSERT_GT(0.14 * 50, 7.0);
  EXPECT_EQ(NearestRank(0.07, 100), 7u);
  EXPECT_EQ(NearestRank(0.14, 50), 7u);
  EXPECT_EQ(NearestRank(0.071, 100), 8u);  // a q that means more still gets the next rank
}

TEST(NearestRankTest, QIsClampedAndNanReadsAsZero) {
  EXPECT_EQ(NearestRank(-1.0, 10), 1u);
  EXPECT_EQ(NearestRank(7.0, 10), 10u);
  EXPECT_EQ(NearestRank(std::nan(""), 10), 1u);
  EXPECT_EQ(NearestRank(std::numeric_limits<double>::infinity(), 10), 10u);
  EXPECT_EQ(NearestRank(0.5, 0), 1u);
}

}  // namespace
}  // namespace hilrig::rig
