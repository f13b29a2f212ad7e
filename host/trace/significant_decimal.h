// Writes a double as decimal text with 9 significant digits, the number format of trace.csv. The
// shortest round-trip form (std::to_chars) cost about 500 instructions per number and was the
// largest single cost of a lockstep tick; this one scales by an exact power of ten, rounds to an
// integer and writes the digits two at a time, for a fraction of that.
//
// Format: the same text as printf("%.9g") (trailing zeros stripped, plain decimal for magnitudes
// in [1e-4, 1e9), "d.dddde-05" / "d.dddde+12" otherwise), except that both zeros are written "0"
// and the non-finite values "nan", "inf" and "-inf" (the sign of a NaN means nothing). The text
// parses back with strtod, std::from_chars, Python's float() and pandas.
//
// Precision: the written value is within one unit in the 9th significant digit of the double
// (relative error below 1e-8). It is the correctly rounded 9-digit value except where the exact
// value lies within a few 1e-16 (relative) of a rounding tie, where it may be the other neighbour.
// The same double always gives the same text, so traces stay byte-reproducible.
#pragma once

#include <cstddef>

namespace hilrig::host {

inline constexpr int kSignificantDigits = 9;
// The longest text: "-1.23456789e-308".
inline constexpr std::size_t kMaxSignificantDecimalChars = 16;

// Writes `value` at `out` (no terminator) and returns the end of the text. `out` must have room
// for kMaxSignificantDecimalChars: all of them are written (a fixed-size copy is cheaper than one
// of the text's length), and those past the returned end are left unspecified.
char* WriteSignificantDecimal(double value, char* out);

}  // namespace hilrig::host
