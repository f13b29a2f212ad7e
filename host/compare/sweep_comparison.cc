#include "host/compare/sweep_comparison.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <utility>

#include "host/compare/change.h"

namespace hilrig::host {
namespace {

// A quantile counts toward the verdict only with this many margins at or below its rank in both
// sweeps: below that it is one or two cases' noise.
constexpr double kMinMarginsUnderGatedQuantile = 5;

double LogChoose(double n, double k) {
  return std::lgamma(n + 1) - std::lgamma(k + 1) - std::lgamma(n - k + 1);
}

proto::Change RateChange(const proto::PassRateChange& row,
                         const proto::CompareTolerances& tolerances) {
  if (row.candidate_rate() == row.base_rate()) return proto::SAME;
  if (row.candidate_rate() > row.base_rate()) return proto::BETTER;
  const bool significant = row.p_value() < 1 - tolerances.confidence();
  const bool beyond = row.base_rate() - row.candidate_rate() > tolerances.pass_rate_drop();
  return significant && beyond ? proto::WORSE : proto::WORSE_WITHIN_TOLERANCE;
}

struct QuantileField {
  const char* name;
  double q;
  double (proto::SweepMarginQuantiles::*value)() const;
};

constexpr std::array<QuantileField, 4> kQuantiles = {{
    {"min", 0.0, &proto::SweepMarginQuantiles::min},
    {"q01", 0.01, &proto::SweepMarginQuantiles::q01},
    {"q10", 0.10, &proto::SweepMarginQuantiles::q10},
    {"q50", 0.50, &proto::SweepMarginQuantiles::q50},
}};

void AddQuantileShifts(const proto::SweepEnvelopeStats& base,
                       const proto::SweepEnvelopeStats& candidate, double margin_fraction,
                       proto::PassRateChange& row) {
  if (!base.has_margin() || !candidate.has_margin()) return;
  const double margins = static_cast<double>(std::min(base.margins(), candidate.margins()));
  for (const auto& field : kQuantiles) {
    auto& shift = *row.add_quantile();
    shift.set_quantile(field.name);
    shift.set_base((base.margin().*field.value)());
    shift.set_candidate((candidate.margin().*field.value)());
    shift.set_gated(field.q * margins >= kMinMarginsUnderGatedQuantile);
    shift.set_change(MarginChange(shift.base(), shift.candidate(), margin_fraction));
  }
}

proto::PassRateChange EnvelopeRow(const proto::SweepEnvelopeStats& base,
                                  const proto::SweepEnvelopeStats* candidate,
                                  const proto::CompareTolerances& tolerances) {
  proto::PassRateChange row;
  row.set_scenario(base.scenario());
  row.set_envelope(base.envelope());
  row.set_base_met(base.met());
  row.set_base_cases(base.cases());
  row.set_base_rate(base.pass_rate());
  if (candidate == nullptr) {
    row.set_p_value(1);
    row.set_change(proto::ONLY_IN_BASE);
    return row;
  }
  row.set_candidate_met(candidate->met());
  row.set_candidate_cases(candidate->cases());
  row.set_candidate_rate(candidate->pass_rate());
  row.set_p_value(FisherLowerTail(base.met(), base.cases(), candidate->met(), candidate->cases()));
  row.set_change(RateChange(row, tolerances));
  // An ablation has no "more room" to grade, as in a run's comparison: only its pass rate counts.
  row.set_expected_fail(base.expected_fail() || candidate->expected_fail());
  if (!row.expected_fail()) AddQuantileShifts(base, *candidate, tolerances.margin_fraction(), row);
  return row;
}

using EnvelopeKey = std::pair<std::string, std::string>;

void AddEnvelopes(const proto::SweepSummary& base, const proto::SweepSummary& candidate,
                  const proto::CompareTolerances& tolerances, proto::SweepComparison& comparison) {
  std::map<EnvelopeKey, const proto::SweepEnvelopeStats*> candidates;
  for (const auto& stats : candidate.envelope()) {
    candidates.emplace(EnvelopeKey{stats.scenario(), stats.envelope()}, &stats);
  }
  for (const auto& stats : base.envelope()) {
    const auto found = candidates.find({stats.scenario(), stats.envelope()});
    *comparison.add_envelope() =
        EnvelopeRow(stats, found == candidates.end() ? nullptr : found->second, tolerances);
  }
}

void AddCriteria(const proto::SweepSummary& base, const proto::SweepSummary& candidate,
                 proto::SweepComparison& comparison) {
  using CriterionKey = std::tuple<std::uint32_t, std::string, std::string>;
  std::map<CriterionKey, bool> candidates;
  for (const auto& check : candidate.check()) {
    candidates.emplace(CriterionKey{check.criterion(), check.scenario(), check.envelope()},
                       check.passed());
  }
  for (const auto& check : base.check()) {
    auto& row = *comparison.add_criterion();
    row.set_criterion(check.criterion());
    row.set_scenario(check.scenario());
    row.set_envelope(check.envelope());
    row.set_base_passed(check.passed());
    const auto found = candidates.find({check.criterion(), check.scenario(), check.envelope()});
    if (found == candidates.end()) {
      row.set_change(proto::ONLY_IN_BASE);
      continue;
    }
    row.set_candidate_passed(found->second);
    row.set_change(found->second == check.passed() ? proto::SAME
                   : check.passed()                ? proto::WORSE
                                                   : proto::BETTER);
  }
}

std::string EnvelopeName(const std::string& scenario, const std::string& envelope) {
  return scenario + "/" + envelope;
}

void GradeSweep(proto::SweepComparison& comparison) {
  // An incomplete sweep on either side proves nothing about the other: never "not worse".
  if (comparison.base_cases() < comparison.base_sweep_cases()) {
    comparison.add_reason(
        "the base sweep is incomplete: " + std::to_string(comparison.base_cases()) + " of " +
        std::to_string(comparison.base_sweep_cases()) + " cases");
  }
  if (comparison.candidate_cases() < comparison.candidate_sweep_cases()) {
    comparison.add_reason(
        "the candidate sweep is incomplete: " + std::to_string(comparison.candidate_cases()) +
        " of " + std::to_string(comparison.candidate_sweep_cases()) + " cases");
  }
  for (const auto& row : comparison.envelope()) {
    const std::string name = EnvelopeName(row.scenario(), row.envelope());
    if (row.change() == proto::ONLY_IN_BASE) {
      comparison.add_reason(name + ": in the base sweep, missing from the candidate");
    } else if (row.change() == proto::WORSE) {
      comparison.add_reason(name + ": the pass rate fell significantly");
    }
    for (const auto& shift : row.quantile()) {
      if (shift.gated() && shift.change() == proto::WORSE) {
        comparison.add_reason(name + ": the margin's " + shift.quantile() +
                              " shrank beyond the tolerance");
      }
    }
  }
  for (const auto& row : comparison.criterion()) {
    if (!CountsAsWorse(row.change())) continue;
    comparison.add_reason("criterion[" + std::to_string(row.criterion()) + "] (" +
                          EnvelopeName(row.scenario(), row.envelope()) +
                          "): met in the base, not in the candidate");
  }
  comparison.set_worse(comparison.reason_size() > 0);
}

}  // namespace

double FisherLowerTail(std::uint64_t base_met, std::uint64_t base_cases,
                       std::uint64_t candidate_met, std::uint64_t candidate_cases) {
  if (base_cases == 0 || candidate_cases == 0) return 1;
  base_met = std::min(base_met, base_cases);
  candidate_met = std::min(candidate_met, candidate_cases);
  const double total = static_cast<double>(base_cases + candidate_cases);
  const double passes = static_cast<double>(base_met + candidate_met);
  const double drawn = static_cast<double>(candidate_cases);
  const double log_all = LogChoose(total, drawn);
  const double lowest = std::max(0.0, passes - static_cast<double>(base_cases));
  double tail = 0;
  for (double x = lowest; x <= static_cast<double>(candidate_met); ++x) {
    tail += std::exp(LogChoose(passes, x) + LogChoose(total - passes, drawn - x) - log_all);
  }
  return std::min(tail, 1.0);
}

proto::SweepComparison CompareSweeps(const proto::SweepSummary& base,
                                     const proto::SweepSummary& candidate,
                                     const proto::CompareTolerances& tolerances) {
  proto::SweepComparison comparison;
  comparison.set_sweep(base.sweep());
  comparison.set_candidate_sweep(candidate.sweep());
  comparison.set_base_cases(base.cases());
  comparison.set_base_sweep_cases(base.sweep_cases());
  comparison.set_candidate_cases(candidate.cases());
  comparison.set_candidate_sweep_cases(candidate.sweep_cases());
  AddEnvelopes(base, candidate, tolerances, comparison);
  AddCriteria(base, candidate, comparison);
  GradeSweep(comparison);
  return comparison;
}

}  // namespace hilrig::host
