// A shard of a sweep: every case whose index is `index` modulo `count` (interleaved, so each shard
// gets its share of every scenario and grid region), run one after another in this process, each
// finished case appended at once as one JSON line to DIR/shards/shard-IIII-of-NNNN.jsonl. A shard
// killed or stopped keeps every case it finished; a line cut by a kill is dropped when the shards
// are read back. `hilrig sweep --jobs N` runs N shards as processes, a Slurm array a shard per
// task; the merge (sweep_merge.h) makes the same results whatever the split.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "host/sweep/case_run.h"
#include "host/sweep/sweep_spec.h"
#include "proto/sweep.pb.h"
#include "rig/result.h"

namespace hilrig::host {

struct ShardSpec {
  std::uint32_t index = 0;  // 0-based; the command line counts from 1 (as Slurm's array ids can)
  std::uint32_t count = 1;
};

// "I/N" with 1 <= I <= N <= 100000; the error quotes the text.
rig::Result<ShardSpec> ParseShardSpec(const std::string& text);

bool InShard(std::uint64_t case_index, const ShardSpec& shard);

// DIR/shards/shard-IIII-of-NNNN.jsonl (I 1-based).
std::string ShardFile(const std::string& out_dir, const ShardSpec& shard);

// Runs the shard's cases in index order, calling `on_case` after each one is written. Fails only
// when the shard file cannot be written (named); a stop request ends it early, keeping what
// finished. Returns the number of cases written.
rig::Result<std::uint64_t> RunShard(
    const LoadedSweep& sweep, const ShardSpec& shard, const std::string& out_dir,
    const CaseRunSetup& setup,
    const std::function<void(const proto::SweepCaseResult&)>& on_case = nullptr);

// One line of a shard file (without its newline) as a case row. Fails, saying why, on what a
// shard does not write whole: a line cut by a kill, text that is not a row's JSON, or a line far
// longer than any row.
rig::Result<proto::SweepCaseResult> ParseShardRow(const std::string& line);

// What the merge found in DIR/shards/*.jsonl.
struct ShardRows {
  std::map<std::uint64_t, proto::SweepCaseResult>
      rows;  // by case index; conflicting cases left out
  // Lines that stand for no case: not a row (a line cut by a kill, garbage, a line past the cap),
  // or a row the check refused (its scenario, seed or values are not its case's).
  std::uint64_t bad_lines = 0;
  // Cases with two rows that differ in more than their timing (real_time_factor, wall_s): neither
  // is taken, and the case counts as not finished.
  std::vector<std::uint64_t> conflicting_cases;
  // Shard files that could not be read (not a regular file, a read error): their cases count as
  // not finished.
  std::uint64_t unreadable_files = 0;
  // "shards/shard-0001-of-0002.jsonl:3: <why>" for the first few bad lines and conflicts.
  std::vector<std::string> problems;
};

// What is wrong with a row that parsed, or nothing when it may stand for its case.
using RowCheck = std::function<std::optional<std::string>(const proto::SweepCaseResult& row)>;

// Every case row in DIR/shards/*.jsonl that `check` accepts, by index. Only regular files are read
// (a FIFO or a device in shards/ is refused by name, never waited on), a line at a time with a cap,
// so a shard file that never ends costs its lines, never memory. A case written twice with the
// same result (a shard run again) is taken once. Fails when the folder cannot be read; a file that
// cannot be is counted and named.
rig::Result<ShardRows> ReadShardRows(const std::string& out_dir, const RowCheck& check);

}  // namespace hilrig::host
