// The lines `hilrig compare` prints: a check's change and numbers, a trace comparison's list capped
// with a count of the rest, a sweep's flipped cases capped likewise, and the verdict with the
// tolerances it was made with.
#include "host/compare/comparison_text.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "host/compare/case_changes.h"

namespace hilrig::host {
namespace {

using ::testing::Contains;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(ComparisonTextTest, ListsChecksAndCapsTheDifferingSignals) {
  proto::RunComparison comparison;
  comparison.set_scenario("hover");
  comparison.set_candidate_scenario("hover");
  comparison.set_base_stop_reason("completed");
  comparison.set_candidate_stop_reason("aborted by envelope low");
  comparison.set_base_passed(true);
  auto* check = comparison.add_check();
  check->set_kind(proto::CheckChange::ENVELOPE);
  check->set_name("altitude");
  check->set_change(proto::WORSE);
  check->set_base_margin(0.04);
  check->set_candidate_margin(0.01);
  check->set_candidate_verdict(proto::FAIL);
  comparison.add_check()->set_name("gone");
  comparison.mutable_check(1)->set_change(proto::ONLY_IN_BASE);
  auto* trace = comparison.mutable_trace();
  trace->set_compared(true);
  trace->set_rows_compared(10);
  for (int i = 0; i < kMaxListedSignals + 3; ++i) {
    auto* difference = trace->add_difference();
    std::string name = "s";  // not "s" + to_string: GCC 12 warns falsely on that (-Wrestrict)
    name += std::to_string(i);
    difference->set_signal(name);
    difference->set_max_abs_difference(1);
  }
  const auto lines = RunComparisonLines(comparison);
  EXPECT_EQ(lines[0], "run hover, seed 0: completed -> aborted by envelope low, PASS -> FAIL");
  EXPECT_THAT(lines[1], HasSubstr("WORSE"));
  EXPECT_THAT(lines[1], HasSubstr("PASS -> FAIL  worst 0  margin 0.04 -> 0.01"));
  EXPECT_EQ(lines[2].find("only in base"), 2u);
  EXPECT_THAT(lines, Contains("  ... and 3 more"));
  EXPECT_THAT(lines, Contains(HasSubstr("s0  ")));
}

TEST(ComparisonTextTest, AnUncomparedTraceSaysWhy) {
  proto::RunComparison comparison;
  comparison.mutable_trace()->set_problem("no readable x/trace.csv");
  EXPECT_THAT(RunComparisonLines(comparison),
              Contains("traces: not compared: no readable x/trace.csv"));
}

TEST(ComparisonTextTest, AnAblationsEnvelopeSaysItsMarginsAreNotGraded) {
  proto::SweepComparison comparison;
  proto::PassRateChange& row = *comparison.add_envelope();
  row.set_scenario("bottle_ablation");
  row.set_envelope("clear_of_ground");
  row.set_base_met(4);
  row.set_base_cases(4);
  row.set_candidate_met(4);
  row.set_candidate_cases(4);
  row.set_p_value(1);
  row.set_change(proto::SAME);
  row.set_expected_fail(true);
  const std::vector<std::string> lines = SweepComparisonLines(comparison);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_THAT(lines[1], HasSubstr("bottle_ablation/clear_of_ground"));
  EXPECT_THAT(lines[1], HasSubstr("(expected to fail: margins not graded)"));
}

// The pass rate held but the margin's 1 % quantile shrank beyond the tolerance: the row is one of
// the reasons the candidate is worse and says so; an ungated shift leaves it "same".
TEST(ComparisonTextTest, AnEnvelopeWorseByItsMarginDoesNotReadSame) {
  proto::SweepComparison comparison;
  proto::PassRateChange& row = *comparison.add_envelope();
  row.set_scenario("balloon_grasp");
  row.set_envelope("grasp_force");
  row.set_base_met(100);
  row.set_base_cases(100);
  row.set_candidate_met(100);
  row.set_candidate_cases(100);
  row.set_p_value(1);
  row.set_change(proto::SAME);
  proto::QuantileShift& shift = *row.add_quantile();
  shift.set_quantile("q01");
  shift.set_base(0.05);
  shift.set_candidate(0.01);
  shift.set_change(proto::WORSE);
  shift.set_gated(false);
  EXPECT_THAT(SweepComparisonLines(comparison)[1], ::testing::StartsWith("  same "));
  shift.set_gated(true);
  EXPECT_THAT(SweepComparisonLines(comparison)[1], ::testing::StartsWith("  WORSE (margin) "));
}

TEST(ComparisonTextTest, TheVerdictStatesItsTolerances) {
  proto::CompareTolerances tolerances;
  tolerances.set_margin_fraction(0.1);
  tolerances.set_pass_rate_drop(0.02);
  tolerances.set_confidence(0.95);
  google::protobuf::RepeatedPtrField<std::string> reasons;
  EXPECT_THAT(VerdictLines(false, reasons, tolerances, false),
              ElementsAre("candidate is not worse than the base (margins may shrink by 10 %)"));
  reasons.Add("envelope x: met in the base, not in the candidate");
  EXPECT_THAT(VerdictLines(true, reasons, tolerances, true),
              ElementsAre("candidate is WORSE than the base (margins may shrink by 10 %, pass "
                          "rates drop by 2 points or without significance at 95 %):",
                          "  envelope x: met in the base, not in the candidate"));
}

// The cases whose verdict changed: a head that counts each kind and says they are not graded,
// a line per listed case with its numbers, values and outcomes, and the rest counted.
TEST(ComparisonTextTest, ASweepsFlippedCasesAreListedUnderTheCriteria) {
  proto::SweepComparison comparison;
  comparison.set_sweep("hover_mass");
  comparison.set_candidate_sweep("hover_mass");
  proto::CaseChanges& cases = *comparison.mutable_cases();
  cases.set_matched(true);
  cases.add_axis("vehicle.mass_kg");
  cases.add_axis("envelopes[1].upper");
  cases.set_matched_cases(40);
  cases.set_now_failing_count(kMaxListedCases + 2);
  for (int i = 0; i < kMaxListedCases; ++i) {
    proto::CaseChange& change = *cases.add_now_failing();
    change.set_base_case(static_cast<std::uint64_t>(i));
    change.set_candidate_case(static_cast<std::uint64_t>(i == 0 ? 5 : i));
    change.set_scenario("hover");
    change.set_seed(2);
    change.add_value(0.6);
    change.add_value(1e-9);
    change.set_base_outcome(proto::SweepCaseResult::PASSED);
    change.set_candidate_outcome(proto::SweepCaseResult::STOPPED);
  }
  cases.set_now_passing_count(1);
  proto::CaseChange& passing = *cases.add_now_passing();
  passing.set_base_case(7);
  passing.set_candidate_case(7);
  passing.set_scenario("hover");
  passing.set_seed(1);
  passing.add_value(0.5);
  passing.add_value(1);
  passing.set_base_outcome(proto::SweepCaseResult::FAILED);
  passing.set_candidate_outcome(proto::SweepCaseResult::PASSED);
  cases.set_only_in_candidate_count(1);
  proto::CaseChange& added = *cases.add_only_in_candidate();
  added.set_candidate_case(41);
  added.set_scenario("hover");
  added.set_seed(3);
  added.add_value(0.5);
  added.add_value(1);
  added.set_candidate_outcome(proto::SweepCaseResult::FAILED);

  const auto lines = SweepComparisonLines(comparison);
  EXPECT_THAT(lines, Contains("cases: 40 in both sweeps, matched by scenario, seed and axis "
                              "values; 22 now failing, 1 now passing, 0 only in the base, 1 only "
                              "in the candidate (listed, not graded: the pass rates, margins and "
                              "criteria decide the verdict)"));
  EXPECT_THAT(lines, Contains("  now failing (passed in the base): 22"));
  EXPECT_THAT(lines, Contains("    case 0 -> 5: hover, seed 2, vehicle.mass_kg=0.6, "
                              "envelopes[1].upper=1e-09: passed -> stopped"));
  EXPECT_THAT(lines, Contains("    ... and 2 more"));
  EXPECT_THAT(lines, Contains("  now passing (did not pass in the base): 1"));
  EXPECT_THAT(lines, Contains("    case 7: hover, seed 1, vehicle.mass_kg=0.5, "
                              "envelopes[1].upper=1: failed -> passed"));
  EXPECT_THAT(lines, Contains("  only in the candidate: 1"));
  EXPECT_THAT(lines, Contains("    case 41: hover, seed 3, vehicle.mass_kg=0.5, "
                              "envelopes[1].upper=1: failed"));
}

TEST(ComparisonTextTest, UnchangedOrUnmatchedCasesTakeOneLine) {
  proto::SweepComparison comparison;
  comparison.mutable_cases()->set_matched(true);
  comparison.mutable_cases()->set_matched_cases(8);
  EXPECT_THAT(SweepComparisonLines(comparison),
              Contains("cases: 8 in both sweeps, matched by scenario, seed and axis values; no "
                       "verdict changed"));
  comparison.mutable_cases()->set_matched(false);
  comparison.mutable_cases()->set_problem("the sweeps have different axes (base: a; candidate: b)");
  EXPECT_THAT(SweepComparisonLines(comparison),
              Contains("cases: not matched: the sweeps have different axes (base: a; candidate: "
                       "b)"));
  EXPECT_EQ(SweepComparisonLines(proto::SweepComparison()).size(), 1u);  // no cases compared
}

}  // namespace
}  // namespace hilrig::host
