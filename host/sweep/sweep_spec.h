// A sweep spec loaded and checked before any case runs (proto/sweep.proto): the sweep file is
// parsed and validated like a scenario (every problem located in the file, all at once), each
// scenario it names is loaded, and each axis's path is checked against each scenario, so a typo in
// a path or an axis that would set a text field is refused up front with its line, never found
// out case by case.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "proto/scenario.pb.h"
#include "proto/sweep.pb.h"
#include "rig/result.h"

namespace hilrig::host {

struct SweepScenario {
  std::string path;  // as opened: the sweep's folder joined with the name in the spec
  proto::Scenario spec;
};

struct LoadedSweep {
  std::string file;
  proto::Sweep spec;
  std::vector<SweepScenario> scenarios;  // in the spec's order
};

// The most cases a sweep may expand to: enough for any regression suite, few enough that the
// per-run rows of runs.csv stay a file a spreadsheet opens.
inline constexpr std::uint64_t kMaxSweepCases = 1'000'000;

// Reads the sweep file (a regular file, at most the scenario size limit) and loads what it names;
// relative scenario paths are taken from the sweep file's folder.
rig::Result<LoadedSweep> LoadSweep(const std::string& path);

// Adds `sets` (`hilrig sweep --set PATH=VALUE,...`) to the sweep's own `set` entries, checked as
// those are: a number at PATH in every scenario, not "seed", not a path an axis sweeps, a finite
// value. Fails on the first bad one, naming it, and then changes nothing.
rig::Result<void> AddSweepSets(LoadedSweep& sweep,
                               const std::vector<std::pair<std::string, double>>& sets);

// Parses and validates sweep text that came from `file_label`; scenario paths are relative to
// `folder`. For tests and for LoadSweep.
rig::Result<LoadedSweep> ParseSweep(const std::string& text, const std::string& file_label,
                                    const std::string& folder);

}  // namespace hilrig::host
