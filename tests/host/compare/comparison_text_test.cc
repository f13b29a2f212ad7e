// The lines `hilrig compare` prints: a check's change and numbers, a trace comparison's list capped
// with a count of the rest, and the verdict with the tolerances it was made with.
#include "host/compare/comparison_text.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace hilrig::host
