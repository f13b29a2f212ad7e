// The batch scripts a sweep hands to Slurm: one job array whose task I runs shard I of N
// (`hilrig sweep DIR/sweep.textproto --out DIR --shard I/N`), and a merge job that runs after the
// array has ended, whatever its tasks' exit codes (`hilrig sweep --merge DIR`), so that a failed
// or cancelled task still leaves the merged results of the rest and an INCOMPLETE verdict. The
// output folder must be on a file system every node sees: the shards write their rows there.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace hilrig::host {

struct SlurmSweepJob {
  std::string name;     // the sweep's name: the jobs are hilrig-NAME and hilrig-NAME-merge
  std::string hilrig;   // absolute path of the hilrig executable the tasks run
  std::string out_dir;  // absolute; holds sweep.textproto, shards/ and slurm/
  std::uint32_t shards = 1;
  std::optional<std::string> partition;
  std::optional<std::uint32_t> max_parallel;  // tasks running at once (the array's %K)
  bool keep_runs = false;
};

// The array's script; each task's output goes to DIR/slurm/shard-I.out. Cannot fail.
std::string ShardArrayScript(const SlurmSweepJob& job);
// The merge's script; its output goes to DIR/slurm/merge.out. Cannot fail.
std::string MergeScript(const SlurmSweepJob& job);

}  // namespace hilrig::host
