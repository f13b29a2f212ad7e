// A sweep's folder between two sweeps. What an earlier sweep wrote there (its shards would mix into
// this merge, its case folders would stand beside these results, its summary would outlive a
// failed merge) is moved aside before a new sweep starts, and put back when the new one cannot
// start, so a refused sweep leaves the folder as it found it.
#pragma once

#include <filesystem>
#include <string>

#include "rig/result.h"

namespace hilrig::host {

// The file holding the sweep as its shards and merge read it.
inline constexpr const char* kResolvedSweepName = "sweep.textproto";

class EarlierSweepAside {
 public:
  // Moves the earlier sweep's outputs (sweep.textproto, shards/, runs/, slurm/, runs.csv,
  // failing.txt, summary.json, map.svg, index.html) into DIR/.previous-sweep, one rename each, so
  // that no earlier map stands beside a new sweep that has none. Fails, naming the path, when one
  // cannot be moved; what was moved is then put back.
  static rig::Result<EarlierSweepAside> Move(const std::string& out_dir);

  // The new sweep has started: the earlier one's outputs are removed.
  void Drop();
  // The new sweep could not start: what it wrote goes and the earlier outputs come back.
  void PutBack();

 private:
  explicit EarlierSweepAside(const std::string& out_dir);

  std::filesystem::path folder_;
  std::filesystem::path previous_;
  bool moved_all_ = false;  // every earlier output is aside; what is at their names is new
};

}  // namespace hilrig::host
