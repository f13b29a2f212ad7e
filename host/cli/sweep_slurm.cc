#include "host/cli/sweep_slurm.h"

#include <filesystem>

#include "host/link/child_process.h"
#include "rig/file_io.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

// `sbatch --parsable` prints "JOBID" or "JOBID;CLUSTER".
std::string JobIdOf(const std::string& output) {
  const std::string first_line = output.substr(0, output.find('\n'));
  return first_line.substr(0, first_line.find(';'));
}

rig::Result<std::string> Submit(const std::string& sbatch, std::vector<std::string> options,
                                const std::string& script, const std::atomic<bool>* stop) {
  std::vector<std::string> argv = {sbatch, "--parsable"};
  argv.insert(argv.end(), options.begin(), options.end());
  argv.push_back(script);
  auto ran = RunCapturingOutput(argv, stop);
  if (!ran) return ran.error();
  const std::string id = JobIdOf(ran.value().output);
  if (id.empty() || id.find_first_not_of("0123456789_") != std::string::npos) {
    return rig::MakeError("sbatch " + script + " " + ran.value().ended + " without a job id" +
                          (ran.value().output.empty() ? "" : ": " + ran.value().output));
  }
  return id;
}

}  // namespace

rig::Result<std::string> CheckSlurmJob(const SlurmSweepJob& job) {
  // #SBATCH lines are not shell: a space cuts the path, and % starts one of Slurm's patterns.
  if (job.out_dir.find_first_of(" \t\n%") != std::string::npos) {
    return rig::MakeError("--slurm: the output folder " + job.out_dir +
                          " has a space or a %, which #SBATCH --output cannot take");
  }
  auto sbatch = FindInPath("sbatch");
  if (!sbatch) {
    return rig::MakeError("--slurm: " + sbatch.error().message +
                          " (Slurm's client, Debian package slurm-client)");
  }
  return sbatch;
}

rig::Result<SlurmSubmission> SubmitSweepToSlurm(const SlurmSweepJob& job, const std::string& sbatch,
                                                bool wait,
                                                const std::atomic<bool>* stop_requested) {
  const fs::path folder = fs::path(job.out_dir) / "slurm";
  std::error_code error;
  fs::create_directories(folder, error);
  if (error) return rig::MakeError("cannot make " + folder.string() + ": " + error.message());
  const std::string shards_script = (folder / "shards.sbatch").string();
  const std::string merge_script = (folder / "merge.sbatch").string();
  for (const auto& [path, text] : {std::pair{shards_script, ShardArrayScript(job)},
                                   std::pair{merge_script, MergeScript(job)}}) {
    if (auto written = rig::WriteFileAtomically(path, text); !written.ok()) return written.error();
  }
  SlurmSubmission submission;
  auto array = Submit(sbatch, {}, shards_script, stop_requested);
  if (!array) return array.error();
  submission.array_job_id = array.value();
  std::vector<std::string> merge_options = {"--dependency=afterany:" + submission.array_job_id};
  if (wait) merge_options.push_back("--wait");
  auto merge = Submit(sbatch, merge_options, merge_script, stop_requested);
  if (!merge) return merge.error();
  submission.merge_job_id = merge.value();
  return submission;
}

}  // namespace hilrig::host
