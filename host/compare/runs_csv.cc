#include "host/compare/runs_csv.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <utility>

#include "host/report/sweep_outcome.h"
#include "rig/bounded_line.h"
#include "rig/command_args.h"
#include "rig/input_file.h"

namespace hilrig::host {
namespace {

using Fields = std::vector<std::string>;

// The records of a CSV stream, each the fields of one line, or of several when a quoted field
// holds a line break, with the line each began on.
class CsvRecords {
 public:
  CsvRecords(std::istream& in, std::string label) : in_(in), label_(std::move(label)) {}

  // The next record, blank lines skipped; nothing at the end.
  rig::Result<std::optional<Fields>> Next();

  // The line the record Next returned last began on, and "LABEL:LINE: " for its errors.
  std::uint64_t line() const { return first_line_; }
  std::string Where() const { return label_ + ":" + std::to_string(first_line_) + ": "; }

 private:
  // Reads the next line into line_: true, or false at the end. Fails on a line past the cap
  // (the rest of the file cannot be told apart from it) and on a read error.
  rig::Result<bool> ReadLine();

  std::istream& in_;
  std::string label_;
  std::string line_;
  std::uint64_t line_number_ = 0;  // of line_
  std::uint64_t first_line_ = 0;
};

rig::Result<bool> CsvRecords::ReadLine() {
  switch (rig::ReadBoundedLine(in_, kMaxRunsCsvLineBytes, line_)) {
    case rig::LineRead::kLine:
      ++line_number_;
      return true;
    case rig::LineRead::kEnd:
      return false;
    case rig::LineRead::kTooLong:
      return rig::MakeError(label_ + ":" + std::to_string(line_number_ + 1) +
                            ": a line longer than " + std::to_string(kMaxRunsCsvLineBytes) +
                            " bytes");
    case rig::LineRead::kReadError:
      break;
  }
  return rig::MakeError("cannot read " + label_ + " after line " + std::to_string(line_number_));
}

rig::Result<std::optional<Fields>> CsvRecords::Next() {
  do {
    auto more = ReadLine();
    if (!more) return more.error();
    if (!more.value()) return std::optional<Fields>();
  } while (line_.empty());
  first_line_ = line_number_;
  enum class State { kFieldStart, kUnquoted, kQuoted, kQuoteClosed };
  State state = State::kFieldStart;
  Fields fields(1);
  for (;;) {
    for (std::size_t i = 0; i < line_.size(); ++i) {
      const char c = line_[i];
      if (state == State::kQuoted) {
        if (c != '"') {
          fields.back() += c;
        } else if (i + 1 < line_.size() && line_[i + 1] == '"') {
          fields.back() += '"';
          ++i;
        } else {
          state = State::kQuoteClosed;
        }
      } else if (c == ',') {
        fields.emplace_back();
        state = State::kFieldStart;
      } else if (state == State::kQuoteClosed) {
        return rig::MakeError(Where() + "field " + std::to_string(fields.size()) +
                              " has text after its closing quote");
      } else if (c == '"' && state == State::kFieldStart) {
        state = State::kQuoted;
      } else {
        fields.back() += c;
        state = State::kUnquoted;
      }
    }
    if (state != State::kQuoted) return std::optional<Fields>(std::move(fields));
    // A line break inside quotes is the field's: the record goes on on the next line.
    fields.back() += '\n';
    auto more = ReadLine();
    if (!more) return more.error();
    if (!more.value()) {
      return rig::MakeError(Where() + "field " + std::to_string(fields.size()) +
                            " opens a quote that never closes");
    }
  }
}

constexpr std::size_t kFirstAxisColumn = 3;  // after case, scenario, seed

// The column of `outcome`, after the axes; fails when `names` is not runs.csv's header.
rig::Result<std::size_t> OutcomeColumn(const Fields& names) {
  if (names.size() > kFirstAxisColumn && names[0] == "case" && names[1] == "scenario" &&
      names[2] == "seed") {
    for (std::size_t column = kFirstAxisColumn; column < names.size(); ++column) {
      if (names[column] == "outcome") return column;
    }
  }
  return rig::MakeError(
      "not the header of a sweep's runs.csv: it starts case,scenario,seed, then a column per axis "
      "and outcome");
}

rig::Result<proto::SweepCaseResult> CaseRow(const Fields& fields, std::size_t columns,
                                            const std::vector<std::string>& axes,
                                            std::size_t outcome_column) {
  if (fields.size() != columns) {
    return rig::MakeError(std::to_string(fields.size()) + " fields where the header has " +
                          std::to_string(columns));
  }
  auto index = rig::ParseNumber<std::uint64_t>(fields[0], "case");
  if (!index) return index.error();
  auto seed = rig::ParseNumber<std::uint64_t>(fields[2], "seed");
  if (!seed) return seed.error();
  proto::SweepCaseResult row;
  row.set_index(index.value());
  row.set_scenario(fields[1]);
  row.set_seed(seed.value());
  for (std::size_t a = 0; a < axes.size(); ++a) {
    auto value = rig::ParseNumber<double>(fields[kFirstAxisColumn + a], axes[a]);
    if (!value) return value.error();
    row.add_value(value.value());
  }
  const auto outcome = OutcomeNamed(fields[outcome_column]);
  if (!outcome) {
    return rig::MakeError("outcome \"" + fields[outcome_column] +
                          "\" is none of passed, failed, stopped, invalid, set_up_failed");
  }
  row.set_outcome(*outcome);
  return row;
}

}  // namespace

rig::Result<SweepCaseRows> ParseRunsCsv(std::istream& in, const std::string& label) {
  CsvRecords records(in, label);
  auto header = records.Next();
  if (!header) return header.error();
  if (!header.value()) return rig::MakeError(label + ": empty, without even a header line");
  const Fields names = std::move(*header.value());
  auto outcome_column = OutcomeColumn(names);
  if (!outcome_column) return rig::InContext(records.Where(), outcome_column.error());
  SweepCaseRows rows;
  rows.axes.assign(names.begin() + kFirstAxisColumn,
                   names.begin() + static_cast<std::ptrdiff_t>(outcome_column.value()));
  std::map<std::uint64_t, std::uint64_t> line_of_case;
  for (;;) {
    auto record = records.Next();
    if (!record) return record.error();
    if (!record.value()) return rows;
    auto row = CaseRow(*record.value(), names.size(), rows.axes, outcome_column.value());
    if (!row) return rig::InContext(records.Where(), row.error());
    const auto [first, fresh] = line_of_case.emplace(row.value().index(), records.line());
    if (!fresh) {
      return rig::MakeError(records.Where() + "case " + std::to_string(row.value().index()) +
                            " again, first on line " + std::to_string(first->second));
    }
    rows.cases.push_back(std::move(row).value());
  }
}

rig::Result<SweepCaseRows> ReadRunsCsv(const std::string& dir) {
  const std::string path = (std::filesystem::path(dir) / "runs.csv").string();
  auto file = rig::InputFile::Open(path);
  if (!file) return file.error();
  return ParseRunsCsv(file.value()->stream(), path);
}

}  // namespace hilrig::host
