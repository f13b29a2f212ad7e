// A sweep folder's runs.csv read back for a comparison of two sweeps (case_changes.h): each
// case's number, scenario, seed, axis values and outcome, as the sweep's merge writes them
// (host/sweep/sweep_merge.h), the axes named by the header's columns between `seed` and
// `outcome`. The file is trusted no further than a shard's: only a regular file is read, a line at
// a time with a cap (rig/input_file.h), and every field the comparison uses is checked, so a
// damaged or hand-edited file is refused with its path and line, never half-read.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

#include "proto/sweep.pb.h"
#include "rig/result.h"

namespace hilrig::host {

// A runs.csv line is a few hundred bytes; a line far longer than any row is not one.
inline constexpr std::size_t kMaxRunsCsvLineBytes = std::size_t{1} << 20;

struct SweepCaseRows {
  std::vector<std::string> axes;  // the axis columns' headers: the sweep's axis paths, in order
  // In the file's order, each with index, scenario, seed, a value per axis and outcome set.
  std::vector<proto::SweepCaseResult> cases;
};

// The rows of the CSV text in `in`, whose errors start "LABEL:LINE: " (or "LABEL: " for the whole
// file). Fields are RFC 4180's (a quoted field may hold commas, doubled quotes and line breaks);
// blank lines are skipped. Fails on the first line that is not a row as the merge writes it: a
// header without case, scenario, seed and outcome, a row with another number of fields than the
// header, a case number or seed that is not a whole number, an axis value that is not a number,
// an outcome that is none of runs.csv's words, a case number twice, an unclosed quote, a line
// longer than kMaxRunsCsvLineBytes, or no header at all.
rig::Result<SweepCaseRows> ParseRunsCsv(std::istream& in, const std::string& label);

// DIR/runs.csv, parsed as above with its path as the label. Fails, naming the file, when it is
// missing, not a regular file or cannot be read.
rig::Result<SweepCaseRows> ReadRunsCsv(const std::string& dir);

}  // namespace hilrig::host
