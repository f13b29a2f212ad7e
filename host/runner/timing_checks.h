// Grades a run's timing (proto::Timing) against the spec's timing envelopes. Only a real-time run
// has timing to grade: in a lockstep run every envelope is listed as not evaluated and passes, so
// the same spec runs in CI (lockstep) and on a bench (real time). A limit whose figure was not
// measured at all (no DUT latency from an in-process DUT) is not evaluated either and says why; a
// figure that is not a finite number fails.
#pragma once

#include <vector>

#include "host/scenario/scenario_config.h"
#include "proto/report.pb.h"

namespace hilrig::host {

// One result per limit the spec sets, in the order of proto::TimingEnvelopes' fields.
std::vector<proto::TimingCheckResult> GradeTiming(const TimingLimits& limits,
                                                  const proto::Timing& timing);

}  // namespace hilrig::host
