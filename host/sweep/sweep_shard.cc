#include "host/sweep/sweep_shard.h"

#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>

#include "host/sweep/sweep_cases.h"
#include "rig/command_args.h"
#include "rig/file_io.h"
#include "rig/input_file.h"

namespace hilrig::host {
namespace {

constexpr std::uint32_t kMaxShards = 100'000;
// A row is a few hundred bytes; a line far longer than any row is not one.
constexpr std::size_t kMaxRowBytes = std::size_t{1} << 20;

std::string JsonLine(const proto::SweepCaseResult& row) {
  std::string json;
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  // Cannot fail for a message of this schema: no Any, no map keys to reject.
  (void)google::protobuf::util::MessageToJsonString(row, &json, options);
  return json + "\n";
}

}  // namespace

rig::Result<ShardSpec> ParseShardSpec(const std::string& text) {
  const std::size_t slash = text.find('/');
  const auto bad = [&text] {
    return rig::MakeError("--shard \"" + text +
                          "\": expected I/N with 1 <= I <= N <= " + std::to_string(kMaxShards));
  };
  if (slash == std::string::npos) return bad();
  auto index = rig::ParseNumber<std::uint32_t>(text.substr(0, slash), "shard");
  auto count = rig::ParseNumber<std::uint32_t>(text.substr(slash + 1), "shard count");
  if (!index || !count || index.value() < 1 || index.value() > count.value() ||
      count.value() > kMaxShards) {
    return bad();
  }
  return ShardSpec{index.value() - 1, count.value()};
}

bool InShard(std::uint64_t case_index, const ShardSpec& shard) {
  return case_index % shard.count == shard.index;
}

std::string ShardFile(const std::string& out_dir, const ShardSpec& shard) {
  char name[64];
  std::snprintf(name, sizeof(name), "shard-%04u-of-%04u.jsonl", shard.index + 1, shard.count);
  return (std::filesystem::path(out_dir) / "shards" / name).string();
}

rig::Result<std::uint64_t> RunShard(
    const LoadedSweep& sweep, const ShardSpec& shard, const std::string& out_dir,
    const CaseRunSetup& setup, const std::function<void(const proto::SweepCaseResult&)>& on_case) {
  const std::string path = ShardFile(out_dir, shard);
  std::error_code error;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), error);
  if (error) return rig::MakeError("cannot make " + path + "'s folder: " + error.message());
  auto file = rig::OutputFile::Create(path, 1 << 16);
  if (!file) return file.error();
  std::uint64_t written = 0;
  const SweepCaseSpace cases(sweep);
  for (std::uint64_t index = shard.index; index < cases.case_count(); index += shard.count) {
    if (setup.stop_requested != nullptr && setup.stop_requested->load()) break;
    const std::optional<proto::SweepCaseResult> row = RunCase(sweep, cases.CaseAt(index), setup);
    if (!row) break;  // interrupted mid-case: not a row
    file.value()->stream() << JsonLine(*row);
    // Each row reaches the file before the next case starts: a kill loses at most the case
    // that was running.
    if (auto flushed = file.value()->Flush(); !flushed.ok()) return flushed.error();
    ++written;
    if (on_case) on_case(*row);
  }
  if (auto closed = file.value()->Close(); !closed.ok()) return closed.error();
  return written;
}

rig::Result<proto::SweepCaseResult> ParseShardRow(const std::string& line) {
  if (line.size() > kMaxRowBytes) {
    return rig::MakeError("a line of " + std::to_string(line.size()) +
                          " bytes, longer than any case row");
  }
  proto::SweepCaseResult row;
  const auto parsed = google::protobuf::util::JsonStringToMessage(line, &row);
  if (!parsed.ok()) return rig::MakeError("not a case row: " + std::string(parsed.message()));
  return row;
}

namespace {

// The problems a merge names; the count says how many more there were.
constexpr std::size_t kMaxNamedProblems = 20;

void AddProblem(ShardRows& found, std::string problem) {
  if (found.problems.size() < kMaxNamedProblems) found.problems.push_back(std::move(problem));
}

// The row without what measures the machine, for telling a re-run's row from a different result.
std::string ResultBytes(proto::SweepCaseResult row) {
  row.clear_real_time_factor();
  row.clear_wall_s();
  return row.SerializeAsString();
}

// Takes a row that passed the check: the first row of a case stands; the same result again is
// taken once; a different one makes the case a conflict.
void TakeRow(proto::SweepCaseResult row, const std::string& where, ShardRows& found,
             std::set<std::uint64_t>& conflicting) {
  const std::uint64_t index = row.index();
  if (conflicting.count(index) != 0) return;
  const auto [at, inserted] = found.rows.try_emplace(index, std::move(row));
  if (inserted || ResultBytes(at->second) == ResultBytes(row)) return;
  conflicting.insert(index);
  found.rows.erase(at);
  AddProblem(found, where + ": case " + std::to_string(index) +
                        " has two different rows; neither is taken");
}

// A file that cannot be read (a FIFO or a device planted in shards/, a read error) is a problem of
// the merge, not its end: its cases count as not finished.
void ReadShardFile(const std::filesystem::path& file, const RowCheck& check, ShardRows& found,
                   std::set<std::uint64_t>& conflicting) {
  const std::string name = "shards/" + file.filename().string();
  auto in = rig::InputFile::Open(file.string());
  if (!in) {
    ++found.unreadable_files;
    AddProblem(found, name + ": " + in.error().message);
    return;
  }
  std::string line;
  for (std::uint64_t number = 1;; ++number) {
    const rig::LineRead read = in.value()->ReadLine(kMaxRowBytes, line);
    if (read == rig::LineRead::kEnd) return;
    if (read == rig::LineRead::kReadError) {
      ++found.unreadable_files;
      AddProblem(found, name + ": " + in.value()->ReadError().message);
      return;
    }
    const std::string where = name + ":" + std::to_string(number);
    if (read == rig::LineRead::kTooLong) {
      // The rest of the file is not read: the line has no end the reader could find cheaply.
      ++found.bad_lines;
      AddProblem(found, where + ": a line longer than " + std::to_string(kMaxRowBytes) +
                            " bytes; the rest of the file is not read");
      return;
    }
    rig::Result<proto::SweepCaseResult> row = ParseShardRow(line);
    std::optional<std::string> refused =
        row.ok() ? check(row.value()) : std::optional<std::string>(row.error().message);
    if (refused) {
      ++found.bad_lines;
      AddProblem(found, where + ": " + *refused);
      continue;
    }
    TakeRow(std::move(row).value(), where, found, conflicting);
  }
}

}  // namespace

rig::Result<ShardRows> ReadShardRows(const std::string& out_dir, const RowCheck& check) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(out_dir) / "shards";
  std::vector<fs::path> files;
  std::error_code error;
  for (fs::directory_iterator entry(folder, error), end; !error && entry != end;
       entry.increment(error)) {
    if (entry->path().extension() == ".jsonl") files.push_back(entry->path());
  }
  if (error) return rig::MakeError("cannot read " + folder.string() + ": " + error.message());
  std::sort(files.begin(), files.end());
  ShardRows found;
  std::set<std::uint64_t> conflicting;
  for (const fs::path& file : files) ReadShardFile(file, check, found, conflicting);
  found.conflicting_cases.assign(conflicting.begin(), conflicting.end());
  return found;
}

}  // namespace hilrig::host
