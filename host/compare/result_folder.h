// What a result folder holds, told from its files: a run's (report.json, trace.csv) or a sweep's
// (summary.json, runs.csv), read for a comparison.
#pragma once

#include <string>

#include "proto/report.pb.h"
#include "proto/sweep.pb.h"
#include "rig/result.h"

namespace hilrig::host {

enum class ResultFolderKind { kRun, kSweep };

// A folder with summary.json is a sweep's, one with report.json a run's. Fails, naming the folder,
// when it is not a folder or holds neither (a sweep's case folders have report.json only, so a
// sweep folder is never taken for a run).
rig::Result<ResultFolderKind> ResultFolderKindOf(const std::string& dir);

// DIR/report.json. Fails, naming the file, when it cannot be read or is not a report.
rig::Result<proto::Report> ReadRunReport(const std::string& dir);

// DIR/summary.json. Fails, naming the file, when it cannot be read or is not a sweep summary.
rig::Result<proto::SweepSummary> ReadSweepSummary(const std::string& dir);

// DIR/trace.csv, the run's trace.
std::string RunTracePath(const std::string& dir);

}  // namespace hilrig::host
