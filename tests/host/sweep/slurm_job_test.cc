// The batch scripts of a sweep on Slurm: the array of shard tasks with its limits, the merge, and
// paths that need quoting in the commands.
#include "host/sweep/slurm_job.h"

#include <gtest/gtest.h>

#include "host/sweep/shell_words.h"

namespace hilrig::host {
namespace {

SlurmSweepJob Job() {
  SlurmSweepJob job;
  job.name = "balloon_seeds";
  job.hilrig = "/opt/hilrig/bin/hilrig";
  job.out_dir = "/shared/sweeps/b1";
  job.shards = 16;
  return job;
}

TEST(SlurmJobTest, TheArrayRunsOneShardPerTask) {
  EXPECT_EQ(ShardArrayScript(Job()),
            "#!/bin/bash\n"
            "#SBATCH --job-name=hilrig-balloon_seeds\n"
            "#SBATCH --output=/shared/sweeps/b1/slurm/shard-%a.out\n"
            "#SBATCH --ntasks=1\n"
            "#SBATCH --cpus-per-task=1\n"
            "#SBATCH --array=1-16\n"
            "# Shard I of 16 of the sweep in /shared/sweeps/b1, written by hilrig sweep --slurm.\n"
            "exec /opt/hilrig/bin/hilrig sweep /shared/sweeps/b1/sweep.textproto --out "
            "/shared/sweeps/b1 --shard \"${SLURM_ARRAY_TASK_ID}/16\"\n");
}

TEST(SlurmJobTest, PartitionParallelismAndKeptRunsReachTheScripts) {
  SlurmSweepJob job = Job();
  job.partition = "short";
  job.max_parallel = 4;
  job.keep_runs = true;
  job.hilrig = "/home/a user/hilrig";
  const std::string array = ShardArrayScript(job);
  EXPECT_NE(array.find("#SBATCH --partition=short\n"), std::string::npos) << array;
  EXPECT_NE(array.find("#SBATCH --array=1-16%4\n"), std::string::npos) << array;
  EXPECT_NE(array.find("exec '/home/a user/hilrig' sweep "), std::string::npos) << array;
  EXPECT_NE(array.find("/16\" --keep-runs\n"), std::string::npos) << array;
  const std::string merge = MergeScript(job);
  EXPECT_NE(merge.find("#SBATCH --job-name=hilrig-balloon_seeds-merge\n"), std::string::npos);
  EXPECT_NE(merge.find("#SBATCH --output=/shared/sweeps/b1/slurm/merge.out\n"), std::string::npos);
  EXPECT_NE(merge.find("#SBATCH --partition=short\n"), std::string::npos);
  EXPECT_NE(merge.find("exec '/home/a user/hilrig' sweep --merge /shared/sweeps/b1\n"),
            std::string::npos)
      << merge;
}

TEST(ShellWordsTest, QuotesWhatTheShellWouldSplitOrExpand) {
  EXPECT_EQ(ShellQuoted("/a/b-c_d.e=1,2:3+4"), "/a/b-c_d.e=1,2:3+4");
  EXPECT_EQ(ShellQuoted("a b"), "'a b'");
  EXPECT_EQ(ShellQuoted("$HOME"), "'$HOME'");
  EXPECT_EQ(ShellQuoted("it's"), "'it'\\''s'");
  EXPECT_EQ(ShellQuoted(""), "''");
}

}  // namespace
}  // namespace hilrig::host
