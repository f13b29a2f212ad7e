// Grades a run's timing (proto::Timing) against the spec's timing envelopes. Only a real-time run
// has timing to grade: in a lockstep run every envelope is listed as not evaluated and passes, so
// the same spec runs in CI (lockstep) and on a bench (real time). A limit whose figure was not
// measured at all (no DUT latency from an in-process DUT) is not evaluated either and says why; a
// figure that is not a finite number fails.
#pragma once

#include <vector>

#include "host/dut/dut_port.h"
#include "host/scenario/scenario_config.h"
#include "proto/report.pb.h"

namespace hilrig::host {

// One result per limit the spec sets, in the order of proto::TimingEnvelopes' fields.
std::vector<proto::TimingCheckResult> GradeTiming(const TimingLimits& limits,
                                                  const proto::Timing& timing);

// The report's target section: what the DUT's target reported, and its work per control step as
// fractions of `control_period_s` at its core clock (0 when the clock is unknown).
proto::Target TargetSection(const TargetSummary& target, double control_period_s);

// One result per target limit the spec sets, in the order of proto::TargetEnvelopes' fields: not
// evaluated without a target (`target` null: a DUT on the host), failed when the target measured
// no work or gave no core clock (the run proved nothing), else graded.
std::vector<proto::TimingCheckResult> GradeTarget(const TargetLimits& limits,
                                                  const proto::Target* target);

}  // namespace hilrig::host
