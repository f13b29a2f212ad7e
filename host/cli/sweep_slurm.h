// `hilrig sweep ... --slurm`: the sweep handed to a Slurm cluster. The batch scripts
// (host/sweep/slurm_job.h) go to DIR/slurm/, then `sbatch` submits the shard array and, depending
// on it, the merge. With `wait` the command returns when the merge has ended (sbatch --wait), and
// the caller prints the merged results as a local sweep would.
#pragma once

#include <atomic>
#include <optional>
#include <ostream>
#include <string>

#include "host/sweep/slurm_job.h"
#include "rig/result.h"

namespace hilrig::host {

struct SlurmSubmission {
  std::string array_job_id;
  std::string merge_job_id;
};

// What can be checked before the sweep changes anything in its folder: the folder's path can be
// used by a batch script (no space or %), and `sbatch` is in PATH. Returns sbatch's path.
rig::Result<std::string> CheckSlurmJob(const SlurmSweepJob& job);

// Writes the scripts and submits them with `sbatch` (from CheckSlurmJob). Fails, saying why, when a
// script cannot be written or sbatch refuses a job (its output quoted).
rig::Result<SlurmSubmission> SubmitSweepToSlurm(const SlurmSweepJob& job, const std::string& sbatch,
                                                bool wait, const std::atomic<bool>* stop_requested);

}  // namespace hilrig::host
