#include "host/compare/trace_difference.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rig/bounded_line.h"

namespace hilrig::host {
namespace {

constexpr const char* kTimeColumn = "time_s";
// A trace row is a few hundred bytes (36 signals at 9 significant digits); a line far longer is not
// a row, and is never held whole.
constexpr std::size_t kMaxTraceLineBytes = std::size_t{1} << 16;

std::vector<std::string> SplitHeader(const std::string& line) {
  std::vector<std::string> names;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    names.push_back(line.substr(start, comma - start));
    if (comma == std::string::npos) return names;
    start = comma + 1;
  }
}

// The row's numbers into `values`; false when a field is not a number or the width is not
// `width`.
bool ParseRow(const std::string& line, std::size_t width, std::vector<double>& values) {
  values.clear();
  const char* at = line.data();
  const char* const end = at + line.size();
  while (true) {
    double value = 0;
    const char* field_end = std::find(at, end, ',');
    const auto [parsed_end, error] = std::from_chars(at, field_end, value);
    if (error != std::errc() || parsed_end != field_end) return false;
    values.push_back(value);
    if (field_end == end) break;
    at = field_end + 1;
  }
  return values.size() == width;
}

struct SignalTally {
  std::string name;
  std::size_t base_column = 0;
  std::size_t candidate_column = 0;
  double max_abs = 0;
  double max_at_s = 0;
  std::optional<double> diverges_at_s;
};

void Tally(SignalTally& tally, double a, double b, double time_s,
           const proto::CompareTolerances& tolerances) {
  if (std::isnan(a) && std::isnan(b)) return;
  const double difference =
      (std::isnan(a) || std::isnan(b)) ? std::numeric_limits<double>::infinity() : std::fabs(a - b);
  if (!(difference > 0)) return;  // equal, or two infinities of one sign
  if (difference > tally.max_abs) {
    tally.max_abs = difference;
    tally.max_at_s = time_s;
  }
  // A tolerance relative to an infinity would allow anything: a value that turns infinite (or
  // NaN) where the other side stays finite, or changes sign at infinity, parts the traces.
  const bool finite = std::isfinite(a) && std::isfinite(b);
  const double allowed =
      tolerances.trace_abs() + tolerances.trace_rel() * std::max(std::fabs(a), std::fabs(b));
  if (!tally.diverges_at_s && !(finite && difference <= allowed)) tally.diverges_at_s = time_s;
}

class TraceReader {
 public:
  TraceReader(std::istream& in, const char* which) : in_(in), which_(which) {}

  // The header's names, or nothing (with `problem` set).
  std::optional<std::vector<std::string>> Header(std::string& problem) {
    std::string line;
    if (!ReadLine(line, problem)) {
      if (problem.empty()) problem = std::string("the ") + which_ + " trace has no header row";
      return std::nullopt;
    }
    auto names = SplitHeader(line);
    if (names.front() != kTimeColumn) {
      problem = std::string("the ") + which_ + " trace's first column is not " + kTimeColumn;
      return std::nullopt;
    }
    width_ = names.size();
    return names;
  }

  // Reads the next row: true with `values` filled, false at the end or on a bad row (then
  // `problem` says which line).
  bool Next(std::vector<double>& values, std::string& problem) {
    std::string line;
    if (!ReadLine(line, problem)) return false;
    ++rows_;
    if (ParseRow(line, width_, values)) return true;
    problem = std::string("the ") + which_ + " trace's line " + std::to_string(rows_ + 1) +
              " is not " + std::to_string(width_) + " numbers";
    return false;
  }

  // Counts the rows left, for the row totals.
  void CountRest(std::string& problem) {
    std::string line;
    while (ReadLine(line, problem)) ++rows_;
  }

  std::uint64_t rows() const { return rows_; }

 private:
  // The next non-empty line; false at the end, at an empty line, or (with `problem` set, unless
  // one is set already) at a line past the cap or a read error.
  bool ReadLine(std::string& line, std::string& problem) {
    const rig::LineRead read = rig::ReadBoundedLine(in_, kMaxTraceLineBytes, line);
    if (read == rig::LineRead::kLine) {
      ++lines_;
      return !line.empty();
    }
    if (read == rig::LineRead::kEnd || !problem.empty()) return false;
    problem = std::string("the ") + which_ + " trace's line " + std::to_string(lines_ + 1) +
              (read == rig::LineRead::kTooLong
                   ? " is longer than " + std::to_string(kMaxTraceLineBytes) + " bytes"
                   : std::string(" cannot be read"));
    return false;
  }

  std::istream& in_;
  const char* which_;
  std::size_t width_ = 0;
  std::uint64_t rows_ = 0;
  std::uint64_t lines_ = 0;  // read whole, the header included
};

std::vector<SignalTally> MatchColumns(const std::vector<std::string>& base,
                                      const std::vector<std::string>& candidate,
                                      proto::TraceComparison& comparison) {
  std::vector<SignalTally> tallies;
  for (std::size_t b = 1; b < base.size(); ++b) {
    const auto found = std::find(candidate.begin() + 1, candidate.end(), base[b]);
    if (found == candidate.end()) {
      comparison.add_only_in_base(base[b]);
    } else {
      SignalTally tally;
      tally.name = base[b];
      tally.base_column = b;
      tally.candidate_column = static_cast<std::size_t>(found - candidate.begin());
      tallies.push_back(std::move(tally));
    }
  }
  for (std::size_t c = 1; c < candidate.size(); ++c) {
    if (std::find(base.begin() + 1, base.end(), candidate[c]) == base.end()) {
      comparison.add_only_in_candidate(candidate[c]);
    }
  }
  return tallies;
}

// Earliest divergence first, then the signals that differ within tolerance, largest first.
void AddDifferences(std::vector<SignalTally>& tallies, proto::TraceComparison& comparison) {
  constexpr double kNever = std::numeric_limits<double>::infinity();
  std::stable_sort(tallies.begin(), tallies.end(), [&](const auto& x, const auto& y) {
    const double x_at = x.diverges_at_s.value_or(kNever);
    const double y_at = y.diverges_at_s.value_or(kNever);
    return x_at != y_at ? x_at < y_at : x.max_abs > y.max_abs;
  });
  for (const auto& tally : tallies) {
    if (!(tally.max_abs > 0)) continue;
    auto& difference = *comparison.add_difference();
    difference.set_signal(tally.name);
    difference.set_max_abs_difference(tally.max_abs);
    difference.set_max_at_s(tally.max_at_s);
    if (tally.diverges_at_s) difference.set_diverges_at_s(*tally.diverges_at_s);
  }
}

}  // namespace

proto::TraceComparison CompareTraces(std::istream& base, std::istream& candidate,
                                     const proto::CompareTolerances& tolerances) {
  proto::TraceComparison comparison;
  TraceReader base_reader(base, "base");
  TraceReader candidate_reader(candidate, "candidate");
  std::string problem;
  const auto base_header = base_reader.Header(problem);
  const auto candidate_header = base_header ? candidate_reader.Header(problem) : std::nullopt;
  if (!base_header || !candidate_header) {
    comparison.set_problem(problem);
    return comparison;
  }
  comparison.set_compared(true);
  auto tallies = MatchColumns(*base_header, *candidate_header, comparison);
  comparison.set_signals_compared(tallies.size());
  std::vector<double> base_row;
  std::vector<double> candidate_row;
  std::uint64_t rows = 0;
  while (base_reader.Next(base_row, problem) && candidate_reader.Next(candidate_row, problem)) {
    const double time_s = base_row.front();
    if (time_s != candidate_row.front()) {
      comparison.set_times_part_at_s(std::min(time_s, candidate_row.front()));
      break;
    }
    ++rows;
    for (auto& tally : tallies) {
      Tally(tally, base_row[tally.base_column], candidate_row[tally.candidate_column], time_s,
            tolerances);
    }
  }
  base_reader.CountRest(problem);
  candidate_reader.CountRest(problem);
  if (!problem.empty()) comparison.set_problem(problem);
  comparison.set_rows_compared(rows);
  comparison.set_base_rows(base_reader.rows());
  comparison.set_candidate_rows(candidate_reader.rows());
  AddDifferences(tallies, comparison);
  return comparison;
}

}  // namespace hilrig::host
