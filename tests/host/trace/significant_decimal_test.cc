#include "host/trace/significant_decimal.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace hilrig::host {
namespace {

std::string Text(double value) {
  char buffer[kMaxSignificantDecimalChars + 8];
  const char* end = WriteSignificantDecimal(value, buffer);
  return std::string(buffer, static_cast<std::size_t>(end - buffer));
}

std::string Printf9(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

// One unit in the 9th significant digit of `value` (finite, non-zero): 10^(floor(log10|v|) - 8).
// The power comes from the printed exponent of %e, which is exact, not from log10.
double NinthDigitUnit(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.16e", value);
  const int exponent = std::atoi(std::strchr(buffer, 'e') + 1);
  return std::pow(10.0, exponent - 8);
}

// The text parses, lies within one 9th-digit unit of the value, and is what printf("%.9g")
// writes (which rounds the exact binary value correctly).
void ExpectNineDigits(double value) {
  const std::string text = Text(value);
  char* end = nullptr;
  const double parsed = std::strtod(text.c_str(), &end);
  ASSERT_EQ(*end, '\0') << text;
  EXPECT_LE(std::abs(parsed - value), NinthDigitUnit(value)) << text << " for " << Printf9(value);
  EXPECT_EQ(text, Printf9(value)) << "value " << std::hexfloat << value;
}

TEST(SignificantDecimalTest, HandPickedTexts) {
  EXPECT_EQ(Text(1.0), "1");
  EXPECT_EQ(Text(-2.5), "-2.5");
  EXPECT_EQ(Text(0.1 + 0.2), "0.3");
  EXPECT_EQ(Text(1.0 / 3.0), "0.333333333");
  EXPECT_EQ(Text(-2.0 / 3.0), "-0.666666667");
  EXPECT_EQ(Text(12345.678), "12345.678");
  EXPECT_EQ(Text(123456789.0), "123456789");
  EXPECT_EQ(Text(100.0), "100");
  EXPECT_EQ(Text(0.0001), "0.0001");
  EXPECT_EQ(Text(0.00012345678912), "0.000123456789");
  EXPECT_EQ(Text(0.000099), "9.9e-05");
  EXPECT_EQ(Text(-2e-17), "-2e-17");
  EXPECT_EQ(Text(1e9), "1e+09");
  EXPECT_EQ(Text(1234567890123.0), "1.23456789e+12");
  EXPECT_EQ(Text(6.02214076e23), "6.02214076e+23");
  EXPECT_EQ(Text(1.5e-300), "1.5e-300");
  EXPECT_EQ(Text(std::numeric_limits<double>::max()), "1.79769313e+308");
  EXPECT_EQ(Text(std::numeric_limits<double>::denorm_min()), "4.94065646e-324");
}

TEST(SignificantDecimalTest, RoundingCarriesIntoTheNextDigit) {
  EXPECT_EQ(Text(9.999999999), "10");
  EXPECT_EQ(Text(9.9999999949), "9.99999999");
  EXPECT_EQ(Text(0.99999999996), "1");
  EXPECT_EQ(Text(99999999.95), "100000000");
  EXPECT_EQ(Text(999999999.6), "1e+09");
  EXPECT_EQ(Text(0.000099999999996), "0.0001");
  EXPECT_EQ(Text(-9.9999999996e-5), "-0.0001");
}

TEST(SignificantDecimalTest, ExactTiesRoundToEvenLikePrintf) {
  EXPECT_EQ(Text(123456788.5), "123456788");
  EXPECT_EQ(Text(123456789.5), "123456790");
  EXPECT_EQ(Text(0.5), "0.5");
}

TEST(SignificantDecimalTest, ZerosAndNonFiniteValues) {
  EXPECT_EQ(Text(0.0), "0");
  EXPECT_EQ(Text(-0.0), "0");
  EXPECT_EQ(Text(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(Text(-std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(Text(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(Text(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(SignificantDecimalTest, IntegersAreWrittenWithoutFraction) {
  for (int i = -100000; i <= 100000; i += 7) {
    ASSERT_EQ(Text(i), std::to_string(i));
  }
  EXPECT_EQ(Text(123456789.0), "123456789");
  EXPECT_EQ(Text(1234567891.0), "1.23456789e+09");
}

TEST(SignificantDecimalTest, RandomMagnitudesFromOneEMinus12ToOneE12) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> exponent(-12.0, 12.0);
  for (int i = 0; i < 200000; ++i) {
    const double magnitude = std::pow(10.0, exponent(rng));
    ExpectNineDigits(i % 2 == 0 ? magnitude : -magnitude);
    if (HasFailure()) return;
  }
}

TEST(SignificantDecimalTest, RandomBitPatterns) {
  std::mt19937_64 rng(7);
  int checked = 0;
  while (checked < 100000) {
    const double value = std::bit_cast<double>(rng());
    if (!std::isfinite(value) || value == 0) continue;
    ExpectNineDigits(value);
    if (HasFailure()) return;
    ++checked;
  }
}

TEST(SignificantDecimalTest, PowersOfTenAndTheirNeighbours) {
  for (int power = -323; power <= 308; ++power) {
    const double value = std::strtod(("1e" + std::to_string(power)).c_str(), nullptr);
    ExpectNineDigits(value);
    ExpectNineDigits(std::nextafter(value, 0.0));
    ExpectNineDigits(std::nextafter(value, std::numeric_limits<double>::infinity()));
    ExpectNineDigits(-value);
    if (HasFailure()) return;
  }
}

// What the trace's columns hold: times on a 10 ms grid, positions of a few metres, angles in
// degrees, forces of a few newtons and noise near zero.
TEST(SignificantDecimalTest, TraceLikeValues) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> metres(0.0, 2.0), noise(0.0, 1e-6), degrees(0.0, 30.0);
  for (int tick = 0; tick < 20000; ++tick) {
    ExpectNineDigits(tick * 0.01);
    ExpectNineDigits(metres(rng));
    ExpectNineDigits(noise(rng));
    ExpectNineDigits(degrees(rng));
    if (HasFailure()) return;
  }
  EXPECT_EQ(Text(12.340000000000001), "12.34");
  EXPECT_EQ(Text(3 * 0.1), "0.3");
}

TEST(SignificantDecimalTest, NeverWritesMoreThanTheDeclaredMaximum) {
  for (const double value : {-1.2345678912345e-308, -1.2345678912345e-100, -0.000123456789123,
                             -123456789.0, -std::numeric_limits<double>::max()}) {
    EXPECT_LE(Text(value).size(), kMaxSignificantDecimalChars) << Text(value);
  }
  EXPECT_EQ(Text(-1.2345678912345e-308).size(), kMaxSignificantDecimalChars);
}

}  // namespace
}  // namespace hilrig::host
