#include "host/sweep/sweep_statistics.h"

#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <unordered_map>
#include <utility>

#include "rig/nearest_rank.h"

namespace hilrig::host {
namespace {

// Acklam's rational approximation of the normal quantile (relative error below 1.15e-9), split at
// the tails where the central form loses accuracy.
double AcklamQuantile(double p) {
  constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                          1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                          6.680131188771972e+01, -1.328068155288572e+01};
  constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                          -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                          3.754408661907416e+00};
  constexpr double kLowTail = 0.02425;
  const auto tail = [&](double q) {
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  };
  if (p < kLowTail) return tail(std::sqrt(-2 * std::log(p)));
  if (p > 1 - kLowTail) return -tail(std::sqrt(-2 * std::log1p(-p)));
  const double q = p - 0.5;
  const double r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
}

// The margin quantiles the summary shows: the low tail, where a sweep's bad cases sit.
proto::SweepMarginQuantiles MarginQuantiles(const SortedSample& margins) {
  proto::SweepMarginQuantiles quantiles;
  quantiles.set_min(*margins.Quantile(0));
  quantiles.set_q01(*margins.Quantile(0.01));
  quantiles.set_q10(*margins.Quantile(0.10));
  quantiles.set_q50(*margins.Quantile(0.50));
  return quantiles;
}

void CountOutcome(proto::SweepCaseResult::Outcome outcome, proto::SweepOutcomeCounts& counts) {
  switch (outcome) {
    case proto::SweepCaseResult::PASSED:
      counts.set_passed(counts.passed() + 1);
      return;
    case proto::SweepCaseResult::FAILED:
      counts.set_failed(counts.failed() + 1);
      return;
    case proto::SweepCaseResult::STOPPED:
      counts.set_stopped(counts.stopped() + 1);
      return;
    case proto::SweepCaseResult::INVALID:
      counts.set_invalid(counts.invalid() + 1);
      return;
    case proto::SweepCaseResult::SET_UP_FAILED:
      counts.set_set_up_failed(counts.set_up_failed() + 1);
      return;
    default:  // OUTCOME_UNSPECIFIED, or a value from a newer writer
      counts.set_unspecified(counts.unspecified() + 1);
      return;
  }
}

// The tallies of one scenario name: their indices in SweepTally::envelopes, by envelope name.
struct ScenarioTallies {
  std::vector<std::size_t> tallies;
  std::unordered_map<std::string, std::size_t> by_envelope;  // into `tallies`
};

// Adds one result of a known scenario to its tallies; margins are gathered in `margins` (one
// vector per tally) and sorted once at the end.
void AddResult(const proto::SweepCaseResult& result, const ScenarioTallies& scenario,
               std::vector<EnvelopeTally>& tallies, std::vector<std::vector<double>>& margins) {
  const bool ran = CaseRan(result.outcome());
  std::vector<bool> recorded(scenario.tallies.size(), false);
  if (ran) {
    for (const proto::SweepCaseResult::Envelope& envelope : result.envelope()) {
      const auto found = scenario.by_envelope.find(envelope.name());
      if (found == scenario.by_envelope.end() || recorded[found->second]) continue;
      recorded[found->second] = true;
      const std::size_t tally = scenario.tallies[found->second];
      proto::SweepEnvelopeStats& stats = tallies[tally].stats;
      if (envelope.met()) stats.set_met(stats.met() + 1);
      margins[tally].push_back(envelope.margin());
    }
  }
  for (std::size_t i = 0; i < scenario.tallies.size(); ++i) {
    proto::SweepEnvelopeStats& stats = tallies[scenario.tallies[i]].stats;
    stats.set_cases(stats.cases() + 1);
    CountOutcome(result.outcome(), *stats.mutable_outcomes());
    if (!ran) {
      stats.set_not_run(stats.not_run() + 1);
    } else if (!recorded[i]) {
      stats.set_unrecorded(stats.unrecorded() + 1);
    }
  }
}

// The figures that follow from the counts and the margins once every result is in.
void Finish(std::vector<double> margins, EnvelopeTally& tally) {
  proto::SweepEnvelopeStats& stats = tally.stats;
  tally.margins = SortedSample(std::move(margins));
  const std::uint64_t cases = stats.cases();
  stats.set_pass_rate(cases > 0 ? static_cast<double>(stats.met()) / static_cast<double>(cases)
                                : 0.0);
  const WilsonBounds bounds = WilsonInterval(stats.met(), cases, kDefaultPassRateConfidence);
  stats.set_pass_rate_lower(bounds.lower);
  stats.set_pass_rate_upper(bounds.upper);
  stats.set_margins(tally.margins.size());
  stats.set_nan_margins(tally.margins.nan_count());
  if (tally.margins.size() > 0) *stats.mutable_margin() = MarginQuantiles(tally.margins);
}

// The cases of the tally that ran: the ones a margin or a verdict can come from.
std::uint64_t CasesRan(const proto::SweepEnvelopeStats& stats) {
  return stats.cases() - stats.not_run();
}

std::string Percent(double fraction) {
  // Four significant digits are enough for a note; the check's fields carry the exact figures.
  char text[32];
  std::snprintf(text, sizeof text, "%.4g %%", fraction * 100);
  return text;
}

proto::SweepCriterionCheck NewCheck(int criterion_index, const std::string& scenario,
                                    const std::string& envelope,
                                    proto::SweepCriterionCheck::Kind kind, double limit) {
  proto::SweepCriterionCheck check;
  check.set_criterion(static_cast<std::uint32_t>(criterion_index));
  check.set_scenario(scenario);
  check.set_envelope(envelope);
  check.set_kind(kind);
  check.set_limit(limit);
  check.set_passed(false);
  return check;
}

proto::SweepCriterionCheck PassRateCheck(int criterion_index, const proto::Criterion& criterion,
                                         const proto::SweepEnvelopeStats& stats) {
  proto::SweepCriterionCheck check =
      NewCheck(criterion_index, stats.scenario(), stats.envelope(),
               proto::SweepCriterionCheck::PASS_RATE, criterion.min_pass_rate());
  if (stats.cases() == 0) {
    check.set_note("no case of the scenario ran");
    return check;
  }
  const double confidence =
      criterion.has_confidence() ? criterion.confidence() : kDefaultPassRateConfidence;
  const double lower = WilsonInterval(stats.met(), stats.cases(), confidence).lower;
  check.set_measured(lower);
  if (CasesRan(stats) == 0) {
    check.set_note("none of the " + std::to_string(stats.cases()) + " cases ran");
    return check;
  }
  check.set_passed(lower >= criterion.min_pass_rate());
  check.set_note(std::to_string(stats.met()) + " of " + std::to_string(stats.cases()) +
                 " cases met; Wilson lower bound at " + Percent(confidence) + " confidence");
  return check;
}

proto::SweepCriterionCheck MarginCheck(int criterion_index, const proto::Criterion& criterion,
                                       const EnvelopeTally& tally) {
  const proto::SweepEnvelopeStats& stats = tally.stats;
  proto::SweepCriterionCheck check =
      NewCheck(criterion_index, stats.scenario(), stats.envelope(),
               proto::SweepCriterionCheck::MARGIN_QUANTILE, criterion.min_margin());
  const std::optional<double> margin = tally.margins.Quantile(criterion.quantile());
  if (!margin) {
    check.set_note(CasesRan(stats) == 0 ? "no case of the scenario ran"
                                        : "no margin recorded in the " +
                                              std::to_string(CasesRan(stats)) + " cases that ran");
    return check;
  }
  check.set_measured(*margin);
  check.set_passed(*margin >= criterion.min_margin());
  check.set_note("the " + Percent(criterion.quantile()) + " quantile of the margins of " +
                 std::to_string(tally.margins.size()) + " cases that ran");
  return check;
}

// The checks of a criterion that names no tallied envelope: one failing check per set limit.
void AddUnmatched(int criterion_index, const proto::Criterion& criterion,
                  std::vector<proto::SweepCriterionCheck>& checks) {
  const auto add = [&](proto::SweepCriterionCheck::Kind kind, double limit) {
    proto::SweepCriterionCheck check =
        NewCheck(criterion_index, criterion.scenario(), criterion.envelope(), kind, limit);
    check.set_note("no envelope of the sweep's scenarios matches the criterion");
    checks.push_back(std::move(check));
  };
  if (criterion.has_min_pass_rate()) {
    add(proto::SweepCriterionCheck::PASS_RATE, criterion.min_pass_rate());
  }
  if (criterion.has_quantile()) {
    add(proto::SweepCriterionCheck::MARGIN_QUANTILE, criterion.min_margin());
  }
}

bool Matches(const proto::Criterion& criterion, const proto::SweepEnvelopeStats& stats) {
  return (criterion.scenario().empty() || criterion.scenario() == stats.scenario()) &&
         (criterion.envelope().empty() || criterion.envelope() == stats.envelope());
}

}  // namespace

bool CaseRan(proto::SweepCaseResult::Outcome outcome) {
  return outcome == proto::SweepCaseResult::PASSED || outcome == proto::SweepCaseResult::FAILED;
}

double StandardNormalQuantile(double probability) {
  if (std::isnan(probability)) return probability;
  if (probability <= 0) return -std::numeric_limits<double>::infinity();
  if (probability >= 1) return std::numeric_limits<double>::infinity();
  const double x = AcklamQuantile(probability);
  // One Halley step on Phi(x) - p brings the approximation to the accuracy of std::erfc.
  const double error = 0.5 * std::erfc(-x / std::numbers::sqrt2) - probability;
  const double u = error * std::sqrt(2 * std::numbers::pi) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

WilsonBounds WilsonInterval(std::uint64_t successes, std::uint64_t trials, double confidence) {
  if (trials == 0 || !(confidence < 1)) return {0, 1};
  successes = std::min(successes, trials);
  const double n = static_cast<double>(trials);
  const double p = static_cast<double>(successes) / n;
  if (!(confidence > 0)) return {p, p};
  const double z = StandardNormalQuantile(0.5 + confidence / 2);
  const double z2_n = z * z / n;
  const double centre = (p + z2_n / 2) / (1 + z2_n);
  const double half_width = z / (1 + z2_n) * std::sqrt(p * (1 - p) / n + z2_n / (4 * n));
  // At 0 and n successes the bound is exactly 0 or 1; the formula would leave a rounding error.
  return {successes == 0 ? 0.0 : std::max(0.0, centre - half_width),
          successes == trials ? 1.0 : std::min(1.0, centre + half_width)};
}

SortedSample::SortedSample(std::vector<double> values) : values_(std::move(values)) {
  const auto nans = std::remove_if(values_.begin(), values_.end(),
                                   [](double value) { return std::isnan(value); });
  nan_count_ = static_cast<std::uint64_t>(values_.end() - nans);
  values_.erase(nans, values_.end());
  std::sort(values_.begin(), values_.end());
}

std::optional<double> SortedSample::Quantile(double q) const {
  if (values_.empty()) return std::nullopt;
  return values_[rig::NearestRank(q, values_.size()) - 1];
}

std::optional<double> NearestRankQuantile(std::vector<double> values, double q) {
  return SortedSample(std::move(values)).Quantile(q);
}

SweepTally TallySweep(const LoadedSweep& sweep,
                      const std::vector<proto::SweepCaseResult>& results) {
  SweepTally tally;
  std::unordered_map<std::string, ScenarioTallies> scenarios;
  for (const SweepScenario& scenario : sweep.scenarios) {
    ScenarioTallies& named = scenarios[scenario.spec.name()];
    for (const proto::Envelope& envelope : scenario.spec.envelopes()) {
      if (named.by_envelope.contains(envelope.name())) continue;
      named.by_envelope.emplace(envelope.name(), named.tallies.size());
      named.tallies.push_back(tally.envelopes.size());
      EnvelopeTally& added = tally.envelopes.emplace_back();
      added.stats.set_scenario(scenario.spec.name());
      added.stats.set_envelope(envelope.name());
      added.stats.set_expected_fail(envelope.expect() == proto::FAIL);
    }
  }
  std::vector<std::vector<double>> margins(tally.envelopes.size());
  for (const proto::SweepCaseResult& result : results) {
    ++tally.cases;
    const auto scenario = scenarios.find(result.scenario());
    if (scenario == scenarios.end()) {
      ++tally.unknown_cases;
      continue;
    }
    AddResult(result, scenario->second, tally.envelopes, margins);
  }
  for (std::size_t i = 0; i < tally.envelopes.size(); ++i) {
    Finish(std::move(margins[i]), tally.envelopes[i]);
  }
  return tally;
}

std::vector<proto::SweepCriterionCheck> GradeCriteria(const proto::Sweep& sweep,
                                                      const std::vector<EnvelopeTally>& tallies) {
  std::vector<proto::SweepCriterionCheck> checks;
  for (int i = 0; i < sweep.criterion_size(); ++i) {
    const proto::Criterion& criterion = sweep.criterion(i);
    bool matched = false;
    for (const EnvelopeTally& tally : tallies) {
      if (!Matches(criterion, tally.stats)) continue;
      matched = true;
      if (criterion.has_min_pass_rate()) checks.push_back(PassRateCheck(i, criterion, tally.stats));
      // An ablation's margin is negative by design: the spec loader refuses a margin criterion
      // that names only such envelopes, and one naming several passes them over.
      if (criterion.has_quantile() && !tally.stats.expected_fail()) {
        checks.push_back(MarginCheck(i, criterion, tally));
      }
    }
    if (!matched) AddUnmatched(i, criterion, checks);
  }
  return checks;
}

proto::SweepSummary SummariseSweep(const LoadedSweep& sweep,
                                   const std::vector<proto::SweepCaseResult>& results) {
  const SweepTally tally = TallySweep(sweep, results);
  proto::SweepSummary summary;
  summary.set_sweep(sweep.spec.name());
  summary.set_cases(tally.cases);
  summary.set_unknown_cases(tally.unknown_cases);
  for (const EnvelopeTally& envelope : tally.envelopes) *summary.add_envelope() = envelope.stats;
  bool passed = true;
  for (proto::SweepCriterionCheck& check : GradeCriteria(sweep.spec, tally.envelopes)) {
    passed = passed && check.passed();
    *summary.add_check() = std::move(check);
  }
  summary.set_passed(passed && summary.check_size() > 0);
  return summary;
}

rig::Result<std::string> SummaryJson(const proto::SweepSummary& summary) {
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  std::string json;
  const auto status = google::protobuf::util::MessageToJsonString(summary, &json, options);
  if (!status.ok()) return rig::MakeError("cannot render the sweep summary: " + status.ToString());
  return json;
}

}  // namespace hilrig::host
