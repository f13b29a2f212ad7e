#include "dut_fw/force_average.h"

#include <gtest/gtest.h>

#include <random>

namespace hilrig::dut_fw {
namespace {

TEST(ForceAverageTest, OneSampleIsNoFilter) {
  ForceAverage<double> average(1);
  EXPECT_EQ(average.Add({1, 2, 3}), Vec3<double>(1, 2, 3));
  EXPECT_EQ(average.Add({4, 5, 6}), Vec3<double>(4, 5, 6));
}

TEST(ForceAverageTest, MeansTheLastSamplesAndForgetsOnReset) {
  ForceAverage<double> average(3);
  EXPECT_EQ(average.Add({3, 0, 0}), Vec3<double>(3, 0, 0));  // fewer than n so far
  EXPECT_EQ(average.Add({6, 0, 0}), Vec3<double>(4.5, 0, 0));
  EXPECT_EQ(average.Add({9, 0, 0}), Vec3<double>(6, 0, 0));
  EXPECT_EQ(average.Add({12, 0, 0}), Vec3<double>(9, 0, 0));  // 3 dropped
  average.Reset();
  EXPECT_EQ(average.Add({1, 1, 1}), Vec3<double>(1, 1, 1));
}

TEST(ForceAverageTest, ClampsTheWindow) {
  EXPECT_EQ(ForceAverage<float>(0).samples(), 1);
  EXPECT_EQ((ForceAverage<float, 8>(100).samples()), 8);
}

// White noise of sigma comes out with sigma / sqrt(n), and a long run keeps the exact mean (the
// running sum is rebuilt every wrap, so it does not drift).
TEST(ForceAverageTest, DividesWhiteNoiseBySqrtNAndDoesNotDrift) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  ForceAverage<double> average(4);
  double sum_squares = 0;
  const int count = 400000;
  Vec3<double> last[4];
  for (int i = 0; i < count; ++i) {
    const Vec3<double> x(1e6 + noise(rng), noise(rng), noise(rng));
    last[i % 4] = x;
    const Vec3<double> mean = average.Add(x);
    if (i >= 3) {
      sum_squares += mean.y() * mean.y();
      const Vec3<double> exact = (last[0] + last[1] + last[2] + last[3]) / 4;
      ASSERT_LT((mean - exact).norm(), 1e-9) << "sample " << i;
    }
  }
  EXPECT_NEAR(std::sqrt(sum_squares / (count - 3)), 0.5, 0.01);
}

}  // namespace
}  // namespace hilrig::dut_fw
