#include "rig/number_text.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <limits>

namespace hilrig::rig {
namespace {

TEST(NumberTextTest, SixSignificantDigitsInTheShortestForm) {
  EXPECT_EQ(NumberText(-1), "-1");
  EXPECT_EQ(NumberText(0), "0");
  EXPECT_EQ(NumberText(1000), "1000");
  EXPECT_EQ(NumberText(0.001), "0.001");
  EXPECT_EQ(NumberText(1e-9), "1e-09");  // std::to_string: "0.000000"
  EXPECT_EQ(NumberText(5.56e299), "5.56e+299");
  EXPECT_EQ(NumberText(2.3456789), "2.34568");
  EXPECT_EQ(NumberText(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(NumberText(std::numeric_limits<double>::quiet_NaN()), "nan");
}

TEST(NumberTextTest, ExactNumbersReadBackAsTheSameDouble) {
  for (double value : {0.1, 1.0 / 3.0, 1e-300, -2.5, 0.0, 123456789.125}) {
    EXPECT_EQ(std::strtod(ExactNumber(value).c_str(), nullptr), value) << ExactNumber(value);
  }
  EXPECT_EQ(ExactNumber(3.5), "3.5");
}

TEST(NumberTextTest, FactorsAreWholeFromTenAndTwoDigitsBelow) {
  EXPECT_EQ(FactorText(2480.4), "2480x");
  EXPECT_EQ(FactorText(10), "10x");
  EXPECT_EQ(FactorText(0.26237), "0.26x");  // an emulated target
  EXPECT_EQ(FactorText(1.5), "1.5x");
  EXPECT_EQ(FactorText(0.00012345), "0.00012x");
  EXPECT_EQ(FactorText(3e20), "3e+20x");
  EXPECT_EQ(FactorText(std::numeric_limits<double>::infinity()), "infx");
}

}  // namespace
}  // namespace hilrig::rig
