// A sweep's results gathered from its shards into the files a person and a CI job read: runs.csv
// (a row per case, in case order), failing.txt (for each case that did not pass, one command that
// runs it alone), summary.json (pass rates and margins per envelope, the criteria's verdict),
// map.svg (which points of two axes passed, sweep_map.h) and index.html, the page that shows them
// (sweep_page.h).
// The files depend on the case rows alone, never on how the cases were split or where they ran,
// so a local sweep and a Slurm one merge to identical files (the real-time factors aside, which
// measure the machine: they stay in runs.csv's last columns).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "host/sweep/sweep_spec.h"
#include "proto/sweep.pb.h"
#include "rig/result.h"

namespace hilrig::host {

struct MergedSweep {
  std::uint64_t cases = 0;              // the sweep's
  std::uint64_t finished = 0;           // rows found
  std::uint64_t bad_lines = 0;          // shard lines that stand for no case (ShardRows::bad_lines)
  std::uint64_t conflicting_cases = 0;  // cases with two different rows: not finished
  std::uint64_t unreadable_files = 0;   // shard files that could not be read
  std::vector<std::string> problems;    // the first few of these, each with its file and line
  std::uint64_t not_passed = 0;
  bool criteria_met = false;    // every criterion passed over a complete sweep
  proto::SweepSummary summary;  // what summary.json holds
};

// runs.csv's text for `rows` (in index order). Columns: case, scenario, seed, one per axis (its
// path), outcome (host/report/sweep_outcome.h's word), then per envelope of the sweep's scenarios
// (in first-seen order) NAME.met, NAME.worst, NAME.margin (empty where a case's scenario has no
// such envelope or it did not run), then detail, and last the two columns that measure the machine,
// not the case: real_time_factor and wall_s.
std::string RunsCsv(const LoadedSweep& sweep,
                    const std::map<std::uint64_t, proto::SweepCaseResult>& rows);

// The command that runs case `row` alone, as `hilrig run` with the case's seed and values, into
// DIR/case-NNNNNNN under `runs_dir`.
std::string ReproduceCommand(const LoadedSweep& sweep, const proto::SweepCaseResult& row,
                             const std::string& hilrig, const std::string& runs_dir);

// Reads the shards under `out_dir`, taking only rows that match their case as the sweep spec makes
// it (scenario, seed, axis values, an outcome consistent with the envelopes), and writes runs.csv,
// failing.txt, summary.json, map.svg for a sweep over two axes (sweep_map.h) and index.html
// (sweep_page.h) there, each whole or not at all. Fails when a shard folder cannot be read or a
// file cannot be written.
rig::Result<MergedSweep> MergeSweep(const LoadedSweep& sweep, const std::string& out_dir,
                                    const std::string& hilrig);

}  // namespace hilrig::host
