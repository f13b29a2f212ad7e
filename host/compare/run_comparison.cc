#include "host/compare/run_comparison.h"

#include <map>
#include <string>

#include "host/compare/change.h"

namespace hilrig::host {
namespace {

proto::Change EnvelopeChange(const proto::EnvelopeResult& base,
                             const proto::EnvelopeResult& candidate, double margin_fraction) {
  if (base.meets_expectation() != candidate.meets_expectation()) {
    return base.meets_expectation() ? proto::WORSE : proto::BETTER;
  }
  // An envelope the spec expects to fail (an ablation) has no "more room" to grade: only whether
  // it still fails as expected counts.
  if (base.expected() == proto::FAIL || candidate.expected() == proto::FAIL) {
    return base.verdict() == candidate.verdict() ? proto::SAME : proto::WORSE_WITHIN_TOLERANCE;
  }
  return MarginChange(base.margin(), candidate.margin(), margin_fraction);
}

// One envelope in either run or both (never neither).
proto::CheckChange EnvelopeRow(const proto::EnvelopeResult* base,
                               const proto::EnvelopeResult* candidate, double margin_fraction) {
  proto::CheckChange row;
  row.set_kind(proto::CheckChange::ENVELOPE);
  row.set_name(base != nullptr ? base->name() : candidate->name());
  if (base != nullptr) {
    row.set_base_met(base->meets_expectation());
    row.set_base_verdict(base->verdict());
    row.set_base_worst(base->worst_value());
    row.set_base_margin(base->margin());
  }
  if (candidate != nullptr) {
    row.set_candidate_met(candidate->meets_expectation());
    row.set_candidate_verdict(candidate->verdict());
    row.set_candidate_worst(candidate->worst_value());
    row.set_candidate_margin(candidate->margin());
  }
  if (base == nullptr) {
    row.set_change(proto::ONLY_IN_CANDIDATE);
  } else if (candidate == nullptr) {
    row.set_change(proto::ONLY_IN_BASE);
  } else {
    row.set_change(EnvelopeChange(*base, *candidate, margin_fraction));
  }
  return row;
}

// A timing or target check in either run or both: passed (or not evaluated) or not. Its value is
// shown, not graded: the check's limit already says what is acceptable.
proto::CheckChange CheckRow(proto::CheckChange::Kind kind, const proto::TimingCheckResult* base,
                            const proto::TimingCheckResult* candidate) {
  proto::CheckChange row;
  row.set_kind(kind);
  row.set_name(base != nullptr ? base->name() : candidate->name());
  if (base != nullptr) {
    row.set_base_met(base->passed());
    row.set_base_worst(base->value());
  }
  if (candidate != nullptr) {
    row.set_candidate_met(candidate->passed());
    row.set_candidate_worst(candidate->value());
  }
  if (base == nullptr) {
    row.set_change(proto::ONLY_IN_CANDIDATE);
  } else if (candidate == nullptr) {
    row.set_change(proto::ONLY_IN_BASE);
  } else if (base->passed() != candidate->passed()) {
    row.set_change(base->passed() ? proto::WORSE : proto::BETTER);
  } else {
    row.set_change(proto::SAME);
  }
  return row;
}

template <typename Result>
std::map<std::string, const Result*> ByName(
    const google::protobuf::RepeatedPtrField<Result>& results) {
  std::map<std::string, const Result*> named;
  for (const auto& result : results) named.emplace(result.name(), &result);  // first one wins
  return named;
}

// A row per name, the base's in its order, then the candidate's own; `make_row(base, candidate)`
// gets nullptr for the run that lacks it. A name repeated within a run counts once, as its first.
template <typename Result, typename MakeRow>
void AddMatched(const google::protobuf::RepeatedPtrField<Result>& base,
                const google::protobuf::RepeatedPtrField<Result>& candidate, MakeRow make_row,
                proto::RunComparison& comparison) {
  const auto bases = ByName(base);
  const auto candidates = ByName(candidate);
  for (const auto& result : base) {
    if (bases.at(result.name()) != &result) continue;
    const auto found = candidates.find(result.name());
    const Result* match = found == candidates.end() ? nullptr : found->second;
    *comparison.add_check() = make_row(&result, match);
  }
  for (const auto& result : candidate) {
    if (candidates.at(result.name()) != &result || bases.contains(result.name())) continue;
    *comparison.add_check() = make_row(static_cast<const Result*>(nullptr), &result);
  }
}

const char* KindText(proto::CheckChange::Kind kind) {
  switch (kind) {
    case proto::CheckChange::TIMING:
      return "timing check ";
    case proto::CheckChange::TARGET:
      return "target check ";
    default:
      return "envelope ";
  }
}

// A run that did not complete, or an envelope that saw no sample, proved nothing: comparing it can
// never say "not worse".
void AddUnprovenReasons(const proto::Report& base, const proto::Report& candidate,
                        proto::RunComparison& comparison) {
  for (const auto& [report, which] :
       {std::pair{&base, "base"}, std::pair{&candidate, "candidate"}}) {
    if (report->stop_kind() != proto::STOP_COMPLETED) {
      comparison.add_reason(std::string("the ") + which + " run did not complete (" +
                            report->stop_reason() + ")");
    }
  }
  for (const auto& envelope : candidate.envelopes()) {
    if (envelope.not_evaluated()) {
      comparison.add_reason("envelope " + envelope.name() +
                            ": not evaluated in the candidate (no samples in its window)");
    }
  }
}

void GradeRun(proto::RunComparison& comparison) {
  for (const auto& check : comparison.check()) {
    if (!CountsAsWorse(check.change())) continue;
    comparison.add_reason(
        std::string(KindText(check.kind())) + check.name() + ": " +
        (check.change() == proto::ONLY_IN_BASE        ? "in the base, missing from the candidate"
         : check.base_met() && !check.candidate_met() ? "met in the base, not in the candidate"
                                                      : "its margin shrank beyond the tolerance"));
  }
  if (comparison.base_passed() && !comparison.candidate_passed()) {
    comparison.add_reason("the base run passed and the candidate did not");
  }
  comparison.set_worse(comparison.reason_size() > 0);
}

}  // namespace

proto::RunComparison CompareRuns(const proto::Report& base, const proto::Report& candidate,
                                 const proto::CompareTolerances& tolerances) {
  proto::RunComparison comparison;
  comparison.set_scenario(base.scenario());
  comparison.set_candidate_scenario(candidate.scenario());
  comparison.set_base_seed(base.seed());
  comparison.set_candidate_seed(candidate.seed());
  comparison.set_base_stop(base.stop_kind());
  comparison.set_candidate_stop(candidate.stop_kind());
  comparison.set_base_stop_reason(base.stop_reason());
  comparison.set_candidate_stop_reason(candidate.stop_reason());
  comparison.set_base_passed(base.passed());
  comparison.set_candidate_passed(candidate.passed());
  const double margin_fraction = tolerances.margin_fraction();
  AddMatched(
      base.envelopes(), candidate.envelopes(),
      [&](const auto* b, const auto* c) { return EnvelopeRow(b, c, margin_fraction); }, comparison);
  for (const auto kind : {proto::CheckChange::TIMING, proto::CheckChange::TARGET}) {
    const bool timing = kind == proto::CheckChange::TIMING;
    AddMatched(
        timing ? base.timing_checks() : base.target_checks(),
        timing ? candidate.timing_checks() : candidate.target_checks(),
        [&](const auto* b, const auto* c) { return CheckRow(kind, b, c); }, comparison);
  }
  AddUnprovenReasons(base, candidate, comparison);
  GradeRun(comparison);
  return comparison;
}

}  // namespace hilrig::host
