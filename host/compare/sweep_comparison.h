// Two sweeps' summaries set side by side, envelope by envelope: the change in pass rate with its
// significance, the shift of each margin quantile, and each criterion's verdict. The candidate is
// worse when a pass rate fell significantly and by more than the tolerance, when a margin quantile
// with enough cases under it shrank beyond the tolerance, when it lost a criterion or an envelope
// the base had, or when its sweep did not finish.
#pragma once

#include <cstdint>

#include "proto/compare.pb.h"
#include "proto/sweep.pb.h"

namespace hilrig::host {

// One-sided Fisher exact test: the probability that the candidate passes `candidate_met` of
// `candidate_cases` or fewer, given the pooled passes, if both builds pass alike (the
// hypergeometric lower tail). 1 when either has no cases. Counts above cases are clamped. Cannot
// fail; O(candidate_cases) with lgamma, no allocation.
double FisherLowerTail(std::uint64_t base_met, std::uint64_t base_cases,
                       std::uint64_t candidate_met, std::uint64_t candidate_cases);

// Compares `candidate` against `base`, envelopes matched by (scenario, envelope) and criteria by
// (index, scenario, envelope). Cannot fail; allocates the result.
proto::SweepComparison CompareSweeps(const proto::SweepSummary& base,
                                     const proto::SweepSummary& candidate,
                                     const proto::CompareTolerances& tolerances);

}  // namespace hilrig::host
