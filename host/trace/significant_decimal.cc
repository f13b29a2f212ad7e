#include "host/trace/significant_decimal.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "rig/check.h"
#include "rig/decimal_digits.h"

namespace hilrig::host {
namespace {

// The significand is a 9-digit integer: value ~ significand * 10^(exponent - 8).
constexpr std::uint64_t kSmallestSignificand = 100'000'000;
constexpr std::uint64_t kSignificandLimit = 1'000'000'000;
// printf's %g switches to the exponent form outside [1e-4, 10^digits).
constexpr int kSmallestPlainExponent = -4;

// Powers of ten that a double holds exactly: scaling by one of them rounds only once.
constexpr int kMaxExactPower = 22;
constexpr std::array<double, kMaxExactPower + 1> kExactPowersOf10 = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

char* Copy(const char* text, std::size_t length, char* out) {
  std::memcpy(out, text, length);
  return out + length;
}

// value * 10^power. A negative power divides by 10^-power, because 10^-k is not exact; powers
// beyond 10^22 take several exact steps (only numbers outside [1e-14, 1e31) need them).
double ScaleByPowerOf10(double value, int power) {
  for (; power > kMaxExactPower; power -= kMaxExactPower) value *= 1e22;
  for (; power < -kMaxExactPower; power += kMaxExactPower) value /= 1e22;
  return power >= 0 ? value * kExactPowersOf10[power] : value / kExactPowersOf10[-power];
}

// The nearest integer, ties to even like printf, for 0 <= x < 2^52: x + 2^52 has no fraction bits
// left, so the addition itself rounds (in the default rounding mode) and the subtraction is exact.
std::uint64_t RoundToInteger(double x) {
  constexpr double kTwoTo52 = 4503599627370496.0;
  return static_cast<std::uint64_t>((x + kTwoTo52) - kTwoTo52);
}

// floor(log10(magnitude)) give or take one, from the binary exponent (log10(2) ~ 78913 / 2^18;
// the shift of a negative product floors, as C++20 defines it).
int DecimalExponentEstimate(double magnitude) {
  const auto biased = static_cast<int>((std::bit_cast<std::uint64_t>(magnitude) >> 52) & 0x7FF);
  if (biased == 0) return static_cast<int>(std::floor(std::log10(magnitude)));  // subnormal
  return ((biased - 1023) * 78913) >> 18;
}

struct Significand {
  std::uint32_t digits;  // in [10^8, 10^9)
  int exponent;          // of the first digit
};

// The magnitude (finite, > 0) rounded to 9 significant digits. A wrong exponent guess shows as a
// rounded integer outside [10^8, 10^9), and so does a carry (9.999999999 -> 10): both rescale once.
Significand RoundToNineDigits(double magnitude) {
  int exponent = DecimalExponentEstimate(magnitude);
  std::uint64_t digits = 0;
  for (int attempt = 0; attempt < 4; ++attempt) {
    digits = RoundToInteger(ScaleByPowerOf10(magnitude, kSignificantDigits - 1 - exponent));
    if (digits >= kSignificandLimit) {
      ++exponent;
    } else if (digits < kSmallestSignificand) {
      --exponent;
    } else {
      break;
    }
  }
  HILRIG_CHECK(digits >= kSmallestSignificand && digits < kSignificandLimit,
               "9-digit rounding did not settle on an exponent");
  return {static_cast<std::uint32_t>(digits), exponent};
}

void WriteNineDigits(std::uint32_t digits, char* out) {
  const std::uint32_t first = digits / 100'000'000;
  const std::uint32_t rest = digits - first * 100'000'000;
  out[0] = static_cast<char>('0' + first);
  const std::uint32_t high = rest / 10'000;
  const std::uint32_t low = rest % 10'000;
  out = rig::WriteTwoDecimalDigits(high / 100, out + 1);
  out = rig::WriteTwoDecimalDigits(high % 100, out);
  out = rig::WriteTwoDecimalDigits(low / 100, out);
  rig::WriteTwoDecimalDigits(low % 100, out);
}

// The layouts below write the nine digits whole and move or overwrite with fixed-size copies,
// which compile to a few loads and stores, instead of copying `length` characters. They write
// past the returned end, so `out` is a scratch buffer with kScratchChars of room.
constexpr std::size_t kScratchChars = 32;

// d[.ddd]e-05, e+12, e-308: printf's form, at least two exponent digits.
char* WriteExponentForm(std::uint32_t digits, std::size_t length, int exponent, char* out) {
  WriteNineDigits(digits, out + 1);
  out[0] = out[1];
  out[1] = '.';
  out += length > 1 ? length + 1 : 1;
  *out++ = 'e';
  *out++ = exponent < 0 ? '-' : '+';
  auto magnitude = static_cast<std::uint32_t>(exponent < 0 ? -exponent : exponent);
  if (magnitude >= 100) {
    *out++ = static_cast<char>('0' + magnitude / 100);
    magnitude %= 100;
  }
  return rig::WriteTwoDecimalDigits(magnitude, out);
}

// 0 <= exponent < 9: the integer part is the first exponent + 1 digits (zeros past `length`),
// and the fraction, if any, moves one place right to make room for the point.
char* WriteAtLeastOne(std::uint32_t digits, std::size_t length, int exponent, char* out) {
  const auto integer_digits = static_cast<std::size_t>(exponent) + 1;
  WriteNineDigits(digits, out);
  if (length <= integer_digits) return out + integer_digits;
  std::memmove(out + integer_digits + 1, out + integer_digits, 8);
  out[integer_digits] = '.';
  return out + length + 1;
}

// -4 <= exponent < 0: "0." and -exponent - 1 zeros before the digits.
char* WriteBelowOne(std::uint32_t digits, std::size_t length, int exponent, char* out) {
  std::memcpy(out, "0.000000", 8);
  out += 2 + static_cast<std::size_t>(-exponent - 1);
  WriteNineDigits(digits, out);
  return out + length;
}

// Significant digits left once trailing zeros go (the first digit is never 0).
std::size_t SignificantLength(std::uint32_t digits) {
  std::size_t length = kSignificantDigits;
  for (; digits % 10 == 0; digits /= 10) --length;
  return length;
}

}  // namespace

char* WriteSignificantDecimal(double value, char* out) {
  if (std::isnan(value)) return Copy("nan", 3, out);
  if (std::isinf(value)) return value > 0 ? Copy("inf", 3, out) : Copy("-inf", 4, out);
  if (value == 0) return Copy("0", 1, out);  // -0 too: the sign of a zero carries nothing here
  std::array<char, kScratchChars> scratch;
  char* text = scratch.data();
  if (value < 0) {
    *text++ = '-';
    value = -value;
  }
  const auto [digits, exponent] = RoundToNineDigits(value);
  const std::size_t length = SignificantLength(digits);
  char* end = nullptr;
  if (exponent < kSmallestPlainExponent || exponent >= kSignificantDigits) {
    end = WriteExponentForm(digits, length, exponent, text);
  } else if (exponent >= 0) {
    end = WriteAtLeastOne(digits, length, exponent, text);
  } else {
    end = WriteBelowOne(digits, length, exponent, text);
  }
  std::memcpy(out, scratch.data(), kMaxSignificantDecimalChars);
  return out + (end - scratch.data());
}

}  // namespace hilrig::host
