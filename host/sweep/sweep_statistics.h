// What a sweep's case results show taken together, and whether they meet the sweep's criteria:
// per envelope of each scenario, the pass rate with its Wilson score interval and the low tail of
// the margin, then each criterion checked against them. Every figure depends on the set of results
// alone, never on their order or on where and when the cases ran, so a sweep run locally and the
// same sweep run in shards summarise to the same JSON.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/sweep/sweep_spec.h"
#include "proto/sweep.pb.h"
#include "rig/result.h"

namespace hilrig::host {

// The standard normal quantile: the x with P(Z <= x) = probability, close to double precision
// (Acklam's rational approximation refined by one Halley step on std::erfc). Cannot fail:
// probability <= 0 gives -infinity, >= 1 gives +infinity, NaN gives NaN.
double StandardNormalQuantile(double probability);

struct WilsonBounds {
  double lower = 0;
  double upper = 1;
};

// The two-sided Wilson score interval at `confidence` for `successes` of `trials`: unlike the
// normal approximation it stays inside [0, 1] and is not zero-width at 0 or n successes, which
// is where a sweep's pass rates sit. Cannot fail: no trials give [0, 1] (nothing is known);
// successes above trials count as trials; a confidence of 0 or less (or NaN) gives the point
// estimate, 1 or more gives [0, 1].
WilsonBounds WilsonInterval(std::uint64_t successes, std::uint64_t trials, double confidence);

// Values sorted once for any number of nearest-rank quantiles. NaNs are set apart and counted
// (a NaN has no rank); infinities are kept, they are ordered.
class SortedSample {
 public:
  SortedSample() = default;
  // O(n log n). Cannot fail.
  explicit SortedSample(std::vector<double> values);

  // The q-quantile by nearest rank (rig::NearestRank: q = 0 the minimum, q = 1 the maximum, the
  // 0.07-quantile of 100 values the 7th). Nothing when there are no values. O(1).
  std::optional<double> Quantile(double q) const;

  std::size_t size() const { return values_.size(); }
  std::uint64_t nan_count() const { return nan_count_; }

 private:
  std::vector<double> values_;  // ascending, no NaN
  std::uint64_t nan_count_ = 0;
};

// SortedSample(values).Quantile(q), for a single quantile.
std::optional<double> NearestRankQuantile(std::vector<double> values, double q);

// Whether a case with `outcome` ran to its envelopes' say (PASSED or FAILED); a case with any other
// outcome met no envelope and has no worst value or margin.
bool CaseRan(proto::SweepCaseResult::Outcome outcome);

// The confidence of the pass-rate interval in the summary, and of a criterion that sets none.
inline constexpr double kDefaultPassRateConfidence = 0.95;

// One envelope of one scenario across the cases: the statistics that go in the summary, and the
// margins themselves, which a criterion's quantile reads at any q.
struct EnvelopeTally {
  proto::SweepEnvelopeStats stats;
  SortedSample margins;  // over the cases that ran and recorded the envelope
};

struct SweepTally {
  std::vector<EnvelopeTally> envelopes;  // scenarios in the sweep's order, envelopes in theirs
  std::uint64_t cases = 0;               // results read, known scenario or not
  std::uint64_t unknown_cases = 0;       // results naming a scenario the sweep does not have
};

// Tallies the results per (scenario, envelope) of the sweep, every pair listed even without a
// case. A result counts under its scenario's name: scenarios of the sweep that share a name are
// pooled (a result carries the name alone), in the order each envelope is first seen. Only the
// outcomes PASSED and FAILED ran; every other outcome counts as not meeting any envelope of the
// scenario and gives no margin. A result that lists an envelope twice counts the first. Cannot
// fail: results of unknown scenarios and envelopes the scenario does not have are left out (the
// former counted). O(results × envelopes per scenario).
SweepTally TallySweep(const LoadedSweep& sweep, const std::vector<proto::SweepCaseResult>& results);

// Checks each criterion (in the spec's order) against every tallied envelope it names (empty
// scenario or envelope: all), one check per limit it sets, per envelope:
//  - PASS_RATE passes when the Wilson lower bound of met / cases at the criterion's confidence
//    (default 0.95) is >= min_pass_rate, and at least one case ran;
//  - MARGIN_QUANTILE passes when the nearest-rank `quantile` of the margins of the cases that
//    ran is >= min_margin (default 0): fewer than `quantile` of them (none, for quantile 0)
//    ended below min_margin. Cases that did not run have no margin and do not count here.
// Cannot fail: a check with nothing to measure (no case ran, no margin recorded) fails with a note
// that says so, and so does a criterion that names no tallied envelope.
std::vector<proto::SweepCriterionCheck> GradeCriteria(const proto::Sweep& sweep,
                                                      const std::vector<EnvelopeTally>& tallies);

// The tally and the checks as one message; `passed` when there are checks and every one passed.
// Cannot fail.
proto::SweepSummary SummariseSweep(const LoadedSweep& sweep,
                                   const std::vector<proto::SweepCaseResult>& results);

// The summary as pretty-printed JSON with the proto's field names and every field shown, so that
// equal summaries give equal bytes. Fails only if protobuf cannot render the message.
rig::Result<std::string> SummaryJson(const proto::SweepSummary& summary);

}  // namespace hilrig::host
