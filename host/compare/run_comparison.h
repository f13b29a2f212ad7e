// Two runs of a scenario set side by side, check by check: each envelope's verdict, worst value
// and margin, each timing and target check, and how each run ended. The candidate is worse when
// it lost a check the base met, when a margin shrank beyond the tolerance, or when the base passed
// and the candidate did not. The traces are compared apart (trace_difference.h): a changed
// controller changes its traces, and where they part says where to look, not whether it regressed.
#pragma once

#include "proto/compare.pb.h"
#include "proto/report.pb.h"

namespace hilrig::host {

// Compares `candidate` against `base` (checks matched by kind and name). Leaves `trace` unset.
// Cannot fail; O(n log n) in the number of checks; allocates the result.
proto::RunComparison CompareRuns(const proto::Report& base, const proto::Report& candidate,
                                 const proto::CompareTolerances& tolerances);

}  // namespace hilrig::host
