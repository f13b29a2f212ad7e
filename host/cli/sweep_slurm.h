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

// Writes the scripts and submits them with the `sbatch` found in PATH. Fails, saying why, when
// the output folder cannot be used by a batch script (a space or a % in its path), a script
// cannot be written, sbatch is missing, or sbatch refuses a job (its output quoted).
rig::Result<SlurmSubmission> SubmitSweepToSlurm(const SlurmSweepJob& job, bool wait,
                                                const std::atomic<bool>* stop_requested);

}  // namespace hilrig::host
