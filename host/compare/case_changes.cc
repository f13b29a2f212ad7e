#include "host/compare/case_changes.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hilrig::host {
namespace {

// What identifies a case across two sweeps: its scenario (numbered in the order first seen),
// seed and values, each value by its bits with every NaN one NaN and -0 as 0, so that values
// compare as numbers and a NaN matches a NaN.
using CaseKey = std::vector<std::uint64_t>;

class CaseKeys {
 public:
  CaseKey Of(const proto::SweepCaseResult& row, const std::vector<double>& values) {
    const auto scenario = scenarios_.emplace(row.scenario(), scenarios_.size()).first->second;
    CaseKey key = {scenario, row.seed()};
    for (const double value : values) {
      key.push_back(std::isnan(value) ? ~std::uint64_t{0}
                                      : std::bit_cast<std::uint64_t>(value == 0 ? 0.0 : value));
    }
    return key;
  }

 private:
  std::map<std::string, std::uint64_t> scenarios_;
};

// For each of the base's axes, its column in the candidate; nothing when the two sweeps' axes
// differ as sets.
std::optional<std::vector<int>> AxisOrder(const std::vector<std::string>& base,
                                          const std::vector<std::string>& candidate) {
  std::vector<std::string> sorted_base = base, sorted_candidate = candidate;
  std::sort(sorted_base.begin(), sorted_base.end());
  std::sort(sorted_candidate.begin(), sorted_candidate.end());
  if (sorted_base != sorted_candidate) return std::nullopt;
  std::vector<int> order;
  std::vector<bool> taken(candidate.size(), false);
  for (const std::string& path : base) {
    for (std::size_t c = 0; c < candidate.size(); ++c) {
      if (taken[c] || candidate[c] != path) continue;
      taken[c] = true;
      order.push_back(static_cast<int>(c));
      break;
    }
  }
  return order;
}

// The case's values in the base's axis order (NaN for a value the row lacks).
std::vector<double> ValuesInOrder(const proto::SweepCaseResult& row,
                                  const std::vector<int>& order) {
  std::vector<double> values;
  for (const int column : order) {
    values.push_back(column < row.value_size() ? row.value(column)
                                               : std::numeric_limits<double>::quiet_NaN());
  }
  return values;
}

std::string Joined(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "" : ", ") + name;
  return joined.empty() ? "none" : joined;
}

enum class Kind { kNowFailing, kNowPassing, kOnlyInBase, kOnlyInCandidate };

// Counts a case of `kind`, and lists it while fewer than kMaxListedCases of its kind are: its
// scenario, seed and `values`, and its number and outcome on each side that has it (`base` or
// `candidate` null on a side that does not).
void AddCase(proto::CaseChanges& changes, Kind kind, const proto::SweepCaseResult* base,
             const proto::SweepCaseResult* candidate, const std::vector<double>& values) {
  google::protobuf::RepeatedPtrField<proto::CaseChange>* listed = nullptr;
  switch (kind) {
    case Kind::kNowFailing:
      changes.set_now_failing_count(changes.now_failing_count() + 1);
      listed = changes.mutable_now_failing();
      break;
    case Kind::kNowPassing:
      changes.set_now_passing_count(changes.now_passing_count() + 1);
      listed = changes.mutable_now_passing();
      break;
    case Kind::kOnlyInBase:
      changes.set_only_in_base_count(changes.only_in_base_count() + 1);
      listed = changes.mutable_only_in_base();
      break;
    case Kind::kOnlyInCandidate:
      changes.set_only_in_candidate_count(changes.only_in_candidate_count() + 1);
      listed = changes.mutable_only_in_candidate();
      break;
  }
  if (listed->size() >= kMaxListedCases) return;
  proto::CaseChange& change = *listed->Add();
  const proto::SweepCaseResult& row = base != nullptr ? *base : *candidate;
  change.set_scenario(row.scenario());
  change.set_seed(row.seed());
  for (const double value : values) change.add_value(value);
  if (base != nullptr) {
    change.set_base_case(base->index());
    change.set_base_outcome(base->outcome());
  }
  if (candidate != nullptr) {
    change.set_candidate_case(candidate->index());
    change.set_candidate_outcome(candidate->outcome());
  }
}

}  // namespace

proto::CaseChanges CompareCases(const SweepCaseRows& base, const SweepCaseRows& candidate) {
  proto::CaseChanges changes;
  for (const std::string& axis : base.axes) changes.add_axis(axis);
  const std::optional<std::vector<int>> order = AxisOrder(base.axes, candidate.axes);
  if (!order) {
    changes.set_problem("the sweeps have different axes (base: " + Joined(base.axes) +
                        "; candidate: " + Joined(candidate.axes) + ")");
    return changes;
  }
  changes.set_matched(true);
  std::vector<int> identity(base.axes.size());
  for (std::size_t a = 0; a < identity.size(); ++a) identity[a] = static_cast<int>(a);
  // The candidate's rows by key, each list last row first, so that the first is taken first.
  CaseKeys keys;
  std::map<CaseKey, std::vector<std::size_t>> unmatched;
  for (std::size_t c = candidate.cases.size(); c-- > 0;) {
    const proto::SweepCaseResult& row = candidate.cases[c];
    unmatched[keys.Of(row, ValuesInOrder(row, *order))].push_back(c);
  }
  std::vector<bool> matched(candidate.cases.size(), false);
  for (const proto::SweepCaseResult& row : base.cases) {
    const std::vector<double> values = ValuesInOrder(row, identity);
    const auto found = unmatched.find(keys.Of(row, values));
    if (found == unmatched.end() || found->second.empty()) {
      AddCase(changes, Kind::kOnlyInBase, &row, nullptr, values);
      continue;
    }
    const std::size_t c = found->second.back();
    found->second.pop_back();
    matched[c] = true;
    changes.set_matched_cases(changes.matched_cases() + 1);
    const bool passed = row.outcome() == proto::SweepCaseResult::PASSED;
    const bool passes = candidate.cases[c].outcome() == proto::SweepCaseResult::PASSED;
    if (passed != passes) {
      AddCase(changes, passed ? Kind::kNowFailing : Kind::kNowPassing, &row, &candidate.cases[c],
              values);
    }
  }
  for (std::size_t c = 0; c < candidate.cases.size(); ++c) {
    if (matched[c]) continue;
    const proto::SweepCaseResult& row = candidate.cases[c];
    AddCase(changes, Kind::kOnlyInCandidate, nullptr, &row, ValuesInOrder(row, *order));
  }
  return changes;
}

}  // namespace hilrig::host
