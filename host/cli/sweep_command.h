// `hilrig sweep`: every case of a sweep spec (proto/sweep.proto) run and graded.
//   hilrig sweep SWEEP.textproto --out DIR [--jobs N] [--keep-runs]
//     runs the cases in N shard processes of this executable (default: one per core) with a
//     progress line, then merges them into DIR/runs.csv, DIR/summary.json and DIR/failing.txt;
//     exit 0 when every criterion is met over every case, 1 when one is not or the sweep was
//     stopped (what finished is kept and merged), 2 for a bad spec or usage.
//   hilrig sweep SWEEP.textproto --out DIR --slurm [--jobs SHARDS] [--partition P]
//                [--max-parallel K] [--wait]
//     submits the shards as one Slurm job array (default: 64 tasks, at most one per case) and the
//     merge as a job that runs after it (host/cli/sweep_slurm.h); with --wait returns when the
//     merge has ended and prints its results, as a local sweep does.
//   hilrig sweep SWEEP.textproto --out DIR --shard I/N
//     runs shard I of N only, into DIR/shards/ (a cluster's array task); prints nothing but errors.
//   hilrig sweep --merge DIR
//     merges the shards in DIR (the sweep is read from DIR/sweep.textproto, written by the first
//     two forms), with the same files and exit code as a local sweep.
#pragma once

#include <string>
#include <vector>

#include "host/cli/cli_args.h"

namespace hilrig::host {

int SweepCommand(const std::vector<std::string>& args, const CliStreams& io);

}  // namespace hilrig::host
