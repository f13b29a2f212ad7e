// Two sweeps' cases side by side: a case that flipped each way, matched by its scenario, seed and
// axis values whatever the rows' order and case numbers; cases one sweep has alone; axes in
// another order; sweeps over different axes; a value listed twice; and the list capped.
#include "host/compare/case_changes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;

constexpr auto kPassed = proto::SweepCaseResult::PASSED;
constexpr auto kFailed = proto::SweepCaseResult::FAILED;
constexpr auto kStopped = proto::SweepCaseResult::STOPPED;

proto::SweepCaseResult Case(std::uint64_t index, std::uint64_t seed, std::vector<double> values,
                            proto::SweepCaseResult::Outcome outcome) {
  proto::SweepCaseResult row;
  row.set_index(index);
  row.set_scenario("hover");
  row.set_seed(seed);
  for (const double value : values) row.add_value(value);
  row.set_outcome(outcome);
  return row;
}

// Mass 0.5 and 0.6, two seeds each, over one axis.
SweepCaseRows Base() {
  return {{"vehicle.mass_kg"},
          {Case(0, 1, {0.5}, kPassed), Case(1, 2, {0.5}, kPassed), Case(2, 1, {0.6}, kFailed),
           Case(3, 2, {0.6}, kPassed)}};
}

TEST(CaseChangesTest, NamesTheCasesThatFlippedEachWayMatchedByTheirValues) {
  // The candidate's rows in another order and numbered otherwise (a sweep that put 0.6 first):
  // case 0 (0.5, seed 1) now fails, stopped; case 2 (0.6, seed 1) now passes.
  SweepCaseRows candidate = {{"vehicle.mass_kg"},
                             {Case(0, 1, {0.6}, kPassed), Case(1, 2, {0.6}, kPassed),
                              Case(2, 1, {0.5}, kStopped), Case(3, 2, {0.5}, kPassed)}};
  const proto::CaseChanges changes = CompareCases(Base(), candidate);
  EXPECT_TRUE(changes.matched());
  EXPECT_THAT(changes.axis(), ElementsAre("vehicle.mass_kg"));
  EXPECT_EQ(changes.matched_cases(), 4u);
  EXPECT_EQ(changes.now_failing_count(), 1u);
  EXPECT_EQ(changes.now_passing_count(), 1u);
  EXPECT_EQ(changes.only_in_base_count(), 0u);
  EXPECT_EQ(changes.only_in_candidate_count(), 0u);
  ASSERT_EQ(changes.now_failing_size(), 1);
  const proto::CaseChange& failing = changes.now_failing(0);
  EXPECT_EQ(failing.scenario(), "hover");
  EXPECT_EQ(failing.seed(), 1u);
  EXPECT_THAT(failing.value(), ElementsAre(0.5));
  EXPECT_EQ(failing.base_case(), 0u);
  EXPECT_EQ(failing.candidate_case(), 2u);
  EXPECT_EQ(failing.base_outcome(), kPassed);
  EXPECT_EQ(failing.candidate_outcome(), kStopped);
  ASSERT_EQ(changes.now_passing_size(), 1);
  EXPECT_EQ(changes.now_passing(0).base_case(), 2u);
  EXPECT_EQ(changes.now_passing(0).candidate_case(), 0u);
  EXPECT_THAT(changes.now_passing(0).value(), ElementsAre(0.6));

  const proto::CaseChanges same = CompareCases(Base(), Base());
  EXPECT_EQ(same.matched_cases(), 4u);
  EXPECT_EQ(same.now_failing_count() + same.now_passing_count(), 0u);
}

// A third seed in the candidate, and the base's seed 2 of mass 0.6 gone from it.
TEST(CaseChangesTest, ACaseOnlyOneSweepHasIsListedAsSuch) {
  SweepCaseRows candidate = Base();
  candidate.cases.erase(candidate.cases.begin() + 3);
  candidate.cases.push_back(Case(4, 3, {0.5}, kFailed));
  const proto::CaseChanges changes = CompareCases(Base(), candidate);
  EXPECT_EQ(changes.matched_cases(), 3u);
  ASSERT_EQ(changes.only_in_base_size(), 1);
  EXPECT_EQ(changes.only_in_base(0).base_case(), 3u);
  EXPECT_FALSE(changes.only_in_base(0).has_candidate_case());
  EXPECT_EQ(changes.only_in_base(0).base_outcome(), kPassed);
  ASSERT_EQ(changes.only_in_candidate_size(), 1);
  EXPECT_EQ(changes.only_in_candidate(0).candidate_case(), 4u);
  EXPECT_FALSE(changes.only_in_candidate(0).has_base_case());
  EXPECT_EQ(changes.only_in_candidate(0).seed(), 3u);
  EXPECT_EQ(changes.only_in_candidate(0).candidate_outcome(), kFailed);
  EXPECT_EQ(changes.now_failing_count() + changes.now_passing_count(), 0u);
}

TEST(CaseChangesTest, AxesAreMatchedByPathAndDifferentAxesMatchNoCase) {
  const SweepCaseRows base = {{"a", "b"}, {Case(0, 1, {1, 10}, kPassed)}};
  const SweepCaseRows swapped = {{"b", "a"}, {Case(0, 1, {10, 1}, kFailed)}};
  const proto::CaseChanges changes = CompareCases(base, swapped);
  EXPECT_TRUE(changes.matched());
  ASSERT_EQ(changes.now_failing_size(), 1);
  EXPECT_THAT(changes.now_failing(0).value(), ElementsAre(1, 10));  // in the base's order

  const SweepCaseRows other = {{"a", "c"}, {Case(0, 1, {1, 10}, kFailed)}};
  const proto::CaseChanges unmatched = CompareCases(base, other);
  EXPECT_FALSE(unmatched.matched());
  EXPECT_EQ(unmatched.problem(), "the sweeps have different axes (base: a, b; candidate: a, c)");
  EXPECT_EQ(unmatched.only_in_base_count() + unmatched.now_failing_count(), 0u);
}

// A list axis that repeats a value makes two cases alike; they pair up in order. A NaN value
// matches a NaN, and -0 matches 0.
TEST(CaseChangesTest, AlikeCasesPairInOrderAndValuesCompareAsNumbers) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const SweepCaseRows base = {{"a"},
                              {Case(0, 1, {1}, kPassed), Case(1, 1, {1}, kFailed),
                               Case(2, 1, {kNaN}, kPassed), Case(3, 1, {-0.0}, kPassed)}};
  const SweepCaseRows candidate = {{"a"},
                                   {Case(0, 1, {1}, kPassed), Case(1, 1, {1}, kPassed),
                                    Case(2, 1, {kNaN}, kFailed), Case(3, 1, {0.0}, kPassed)}};
  const proto::CaseChanges changes = CompareCases(base, candidate);
  EXPECT_EQ(changes.matched_cases(), 4u);
  ASSERT_EQ(changes.now_passing_size(), 1);
  EXPECT_EQ(changes.now_passing(0).base_case(), 1u);
  EXPECT_EQ(changes.now_passing(0).candidate_case(), 1u);
  ASSERT_EQ(changes.now_failing_size(), 1);
  EXPECT_EQ(changes.now_failing(0).base_case(), 2u);
  EXPECT_TRUE(std::isnan(changes.now_failing(0).value(0)));
}

TEST(CaseChangesTest, TheListsAreCappedAndTheCountsCountEveryCase) {
  SweepCaseRows base = {{"a"}, {}}, candidate = {{"a"}, {}};
  const auto cases = static_cast<std::uint64_t>(kMaxListedCases) + 7;
  for (std::uint64_t i = 0; i < cases; ++i) {
    base.cases.push_back(Case(i, 1, {static_cast<double>(i)}, kPassed));
    candidate.cases.push_back(Case(i, 1, {static_cast<double>(i)}, kFailed));
  }
  const proto::CaseChanges changes = CompareCases(base, candidate);
  EXPECT_EQ(changes.now_failing_count(), cases);
  ASSERT_EQ(changes.now_failing_size(), kMaxListedCases);
  EXPECT_EQ(changes.now_failing(0).base_case(), 0u);  // the first ones, in the base's order
  EXPECT_EQ(changes.now_failing(kMaxListedCases - 1).base_case(), kMaxListedCases - 1u);
}

}  // namespace
}  // namespace hilrig::host
