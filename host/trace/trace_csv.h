// Writes trace samples as CSV with a header row. Numbers are printed in their shortest form that
// reads back to the same double (std::to_chars), which is both fast enough for the lockstep loop
// and byte-reproducible: the same run gives the same file.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <ostream>

#include "host/trace/trace_sample.h"

namespace hilrig::host {

class TraceCsvWriter {
 public:
  static constexpr std::size_t kColumnCount = 36;

  // Writes the header at once; `out` must outlive the writer.
  explicit TraceCsvWriter(std::ostream& out);

  void Write(const TraceSample& sample);

 private:
  // One column's text in the previous row. Shortest round-trip formatting is the writer's main
  // cost, and many columns (reference, set-points, the 50 Hz tactile estimates, flags) repeat from
  // one row to the next; the same bits always give the same text, so repeating it is exact.
  struct ColumnText {
    std::uint64_t bits = 0;
    bool valid = false;
    std::uint8_t length = 0;
    std::array<char, 32> text{};  // the longest shortest-form double has 24 characters
  };

  // Appends `value` and a separator; the row's last separator becomes the newline.
  void Append(double value);

  std::ostream& out_;
  std::array<ColumnText, kColumnCount> previous_{};
  std::size_t column_ = 0;
  std::array<char, kColumnCount * 33> line_{};
  std::size_t line_length_ = 0;
};

}  // namespace hilrig::host
