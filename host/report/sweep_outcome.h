// The words a sweep case's outcome is written with in runs.csv and on a sweep's page ("passed",
// "failed", ...), and back: the sweep's merge writes them (host/sweep/sweep_merge.h) and a
// comparison of two sweeps reads them (host/compare/runs_csv.h), through this one table.
#pragma once

#include <optional>
#include <string_view>

#include "proto/sweep.pb.h"

namespace hilrig::host {

// "passed", "failed", "stopped", "invalid", "set_up_failed"; "unknown" for an outcome this build
// does not know.
const char* OutcomeName(proto::SweepCaseResult::Outcome outcome);

// The outcome `name` stands for; nothing for any other word ("unknown" among them).
std::optional<proto::SweepCaseResult::Outcome> OutcomeNamed(std::string_view name);

}  // namespace hilrig::host
