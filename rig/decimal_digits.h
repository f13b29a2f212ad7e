// Two decimal digits per table look-up, for the number writers of the lockstep loop (candump
// timestamps, trace numbers): writing a pair of digits from a "00".."99" table halves the
// divisions of a digit-by-digit loop and needs no format call.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>

namespace hilrig::rig {

inline constexpr std::array<char, 200> kDecimalDigitPairs = [] {
  std::array<char, 200> pairs{};
  for (int i = 0; i < 100; ++i) {
    pairs[2 * i] = static_cast<char>('0' + i / 10);
    pairs[2 * i + 1] = static_cast<char>('0' + i % 10);
  }
  return pairs;
}();

// Writes `two_digits` (< 100) as exactly two characters; returns the end.
inline char* WriteTwoDecimalDigits(std::uint32_t two_digits, char* out) {
  std::memcpy(out, &kDecimalDigitPairs[2 * two_digits], 2);
  return out + 2;
}

}  // namespace hilrig::rig
