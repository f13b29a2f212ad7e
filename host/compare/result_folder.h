// What a result folder holds, told from its files: a run's (report.json, trace.csv), a sweep's
// (summary.json, runs.csv) or a folder run's (a run folder per scenario), read for a comparison.
#pragma once

#include <string>
#include <vector>

#include "proto/report.pb.h"
#include "proto/sweep.pb.h"
#include "rig/result.h"

namespace hilrig::host {

enum class ResultFolderKind { kRun, kSweep, kSuite };

// A folder with summary.json is a sweep's, one with report.json a run's, one with neither but a
// subfolder holding report.json a folder run's (`hilrig run DIR/ --out OUT`, ./scripts/run). Fails,
// naming the folder, when it is not a folder or holds none of them (a sweep's case folders sit
// under runs/, so a sweep folder is never taken for a folder run).
rig::Result<ResultFolderKind> ResultFolderKindOf(const std::string& dir);

// DIR/report.json. Fails, naming the file, when it cannot be read or is not a report.
rig::Result<proto::Report> ReadRunReport(const std::string& dir);

// DIR/summary.json. Fails, naming the file, when it cannot be read or is not a sweep summary.
rig::Result<proto::SweepSummary> ReadSweepSummary(const std::string& dir);

// DIR/trace.csv, the run's trace.
std::string RunTracePath(const std::string& dir);

// The run folders of a folder run: the names of DIR's subfolders that hold report.json, sorted.
// O(entries of DIR); fails only when DIR cannot be listed.
rig::Result<std::vector<std::string>> SuiteRunNames(const std::string& dir);

}  // namespace hilrig::host
