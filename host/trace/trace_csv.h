// Writes trace samples as CSV with a header row. Numbers have 9 significant digits
// (WriteSignificantDecimal: within one unit in the 9th digit of the double, "0" for zero, "nan",
// "inf", "-inf"), which is fast enough for the lockstep loop, far finer than any signal's noise or
// envelope, and byte-reproducible: the same run gives the same file.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <ostream>

#include "host/trace/significant_decimal.h"
#include "host/trace/trace_sample.h"

namespace hilrig::host {

class TraceCsvWriter {
 public:
  // The scalar columns, then each pad's true force and each pad's DUT estimate.
  static constexpr std::size_t kScalarColumnCount = 39;
  static constexpr std::size_t kColumnCount = kScalarColumnCount + 2 * kTracePadCount;

  // Writes the header at once; `out` must outlive the writer.
  explicit TraceCsvWriter(std::ostream& out);

  void Write(const TraceSample& sample);

 private:
  // One column's text in the previous row. Many columns (reference, set-points, the 50 Hz tactile
  // estimates, flags) repeat from one row to the next; the same bits always give the same text, so
  // copying it is exact and cheaper than formatting again.
  struct ColumnText {
    std::uint64_t bits = 0;
    std::uint8_t length = 0;  // 0: no previous row yet
    std::array<char, kMaxSignificantDecimalChars> text{};
  };

  // Writes `value` and a separator at `out`; returns the end.
  static char* AppendColumn(double value, ColumnText& previous, char* out);

  std::ostream& out_;
  std::array<ColumnText, kColumnCount> previous_{};
  // Every column copies its whole text buffer, so the line has room for that many per column.
  std::array<char, kColumnCount*(kMaxSignificantDecimalChars + 1)> line_{};
};

}  // namespace hilrig::host
