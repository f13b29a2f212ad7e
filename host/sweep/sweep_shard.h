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
#include <string>

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

// Every case row in DIR/shards/*.jsonl, by index. A line that does not parse (the last line of a
// shard that was killed while writing) is skipped and counted in `*bad_lines`. Fails when the
// folder cannot be read. A case present twice (a shard run again) keeps its later row.
rig::Result<std::map<std::uint64_t, proto::SweepCaseResult>> ReadShardRows(
    const std::string& out_dir, std::uint64_t* bad_lines);

}  // namespace hilrig::host
