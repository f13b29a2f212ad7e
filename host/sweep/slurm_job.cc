#include "host/sweep/slurm_job.h"

#include <sstream>

#include "host/sweep/shell_words.h"

namespace hilrig::host {
namespace {

// The #SBATCH lines both jobs share.
void CommonHeader(const SlurmSweepJob& job, const std::string& job_name, const std::string& output,
                  std::ostringstream& script) {
  script << "#!/bin/bash\n"
         << "#SBATCH --job-name=" << job_name << "\n"
         << "#SBATCH --output=" << output << "\n"
         << "#SBATCH --ntasks=1\n"
         << "#SBATCH --cpus-per-task=1\n";
  if (job.partition) script << "#SBATCH --partition=" << *job.partition << "\n";
}

}  // namespace

std::string ShardArrayScript(const SlurmSweepJob& job) {
  std::ostringstream script;
  // #SBATCH lines are not shell: a path with a space there would be cut; the %a is Slurm's.
  CommonHeader(job, "hilrig-" + job.name, job.out_dir + "/slurm/shard-%a.out", script);
  script << "#SBATCH --array=1-" << job.shards;
  if (job.max_parallel) script << "%" << *job.max_parallel;
  script << "\n"
         << "# Shard I of " << job.shards << " of the sweep in " << job.out_dir
         << ", written by hilrig sweep --slurm.\n"
         << "exec " << ShellQuoted(job.hilrig) << " sweep "
         << ShellQuoted(job.out_dir + "/sweep.textproto") << " --out " << ShellQuoted(job.out_dir)
         << " --shard \"${SLURM_ARRAY_TASK_ID}/" << job.shards << "\""
         << (job.keep_runs ? " --keep-runs" : "") << "\n";
  return script.str();
}

std::string MergeScript(const SlurmSweepJob& job) {
  std::ostringstream script;
  CommonHeader(job, "hilrig-" + job.name + "-merge", job.out_dir + "/slurm/merge.out", script);
  script << "# Gathers the shards of the sweep in " << job.out_dir
         << " once its array has ended, written by hilrig sweep --slurm.\n"
         << "exec " << ShellQuoted(job.hilrig) << " sweep --merge " << ShellQuoted(job.out_dir)
         << "\n";
  return script.str();
}

}  // namespace hilrig::host
