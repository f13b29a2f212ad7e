// Two run reports compared check by check: what makes a candidate worse (a lost expectation, a
// margin shrunk beyond tolerance, a lost check, a base that passed and a candidate that did not)
// and what does not (a margin within tolerance, an ablation's expected failure, a new envelope).
#include "host/compare/run_comparison.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

proto::CompareTolerances Tolerances() {
  proto::CompareTolerances tolerances;
  tolerances.set_margin_fraction(0.1);
  return tolerances;
}

proto::EnvelopeResult* AddEnvelope(proto::Report& report, const std::string& name, bool met,
                                   double margin, proto::Verdict expected = proto::PASS) {
  auto* envelope = report.add_envelopes();
  envelope->set_name(name);
  envelope->set_expected(expected);
  envelope->set_meets_expectation(met);
  envelope->set_verdict(met == (expected == proto::PASS) ? proto::PASS : proto::FAIL);
  envelope->set_margin(margin);
  envelope->set_worst_value(1 - margin);
  return envelope;
}

proto::Report Passing() {
  proto::Report report;
  report.set_scenario("balloon_grasp");
  report.set_passed(true);
  report.set_stop_kind(proto::STOP_COMPLETED);
  AddEnvelope(report, "grasp_force", true, 0.05);
  AddEnvelope(report, "altitude_error", true, 0.04);
  AddEnvelope(report, "ablated", true, -0.3, proto::FAIL);
  return report;
}

const proto::CheckChange& Check(const proto::RunComparison& comparison, const std::string& name) {
  for (const auto& check : comparison.check()) {
    if (check.name() == name) return check;
  }
  ADD_FAILURE() << "no check " << name;
  static const proto::CheckChange kNone;
  return kNone;
}

TEST(CompareRunsTest, TheSameReportIsNotWorse) {
  const auto comparison = CompareRuns(Passing(), Passing(), Tolerances());
  EXPECT_FALSE(comparison.worse());
  ASSERT_EQ(comparison.check_size(), 3);
  for (const auto& check : comparison.check()) EXPECT_EQ(check.change(), proto::SAME);
  EXPECT_EQ(comparison.check(0).name(), "grasp_force");  // the report's order, not sorted
}

TEST(CompareRunsTest, ALostExpectationIsWorseAndSaysWhy) {
  proto::Report candidate = Passing();
  candidate.set_passed(false);
  candidate.mutable_envelopes(0)->set_meets_expectation(false);
  candidate.mutable_envelopes(0)->set_verdict(proto::FAIL);
  candidate.mutable_envelopes(0)->set_margin(-0.02);
  const auto comparison = CompareRuns(Passing(), candidate, Tolerances());
  EXPECT_TRUE(comparison.worse());
  EXPECT_EQ(Check(comparison, "grasp_force").change(), proto::WORSE);
  EXPECT_EQ(Check(comparison, "grasp_force").candidate_verdict(), proto::FAIL);
  ASSERT_EQ(comparison.reason_size(), 2);
  EXPECT_THAT(comparison.reason(0), HasSubstr("grasp_force: met in the base, not in the"));
  EXPECT_THAT(comparison.reason(1), HasSubstr("the base run passed and the candidate did not"));
  // The other way round it is better, and not worse.
  const auto back = CompareRuns(candidate, Passing(), Tolerances());
  EXPECT_FALSE(back.worse());
  EXPECT_EQ(Check(back, "grasp_force").change(), proto::BETTER);
}

TEST(CompareRunsTest, AMarginShrinkCountsBeyondTheTolerance) {
  proto::Report within = Passing();
  within.mutable_envelopes(0)->set_margin(0.046);  // 8 % less room
  EXPECT_FALSE(CompareRuns(Passing(), within, Tolerances()).worse());
  EXPECT_EQ(Check(CompareRuns(Passing(), within, Tolerances()), "grasp_force").change(),
            proto::WORSE_WITHIN_TOLERANCE);
  proto::Report beyond = Passing();
  beyond.mutable_envelopes(1)->set_margin(0.03);  // 25 % less room, still passing
  const auto comparison = CompareRuns(Passing(), beyond, Tolerances());
  EXPECT_TRUE(comparison.worse());
  EXPECT_EQ(Check(comparison, "altitude_error").change(), proto::WORSE);
  ASSERT_EQ(comparison.reason_size(), 1);
  EXPECT_THAT(comparison.reason(0), HasSubstr("margin shrank beyond the tolerance"));
}

TEST(CompareRunsTest, AnExpectedFailureIsGradedByItsVerdictOnly) {
  proto::Report candidate = Passing();
  candidate.mutable_envelopes(2)->set_margin(-0.9);  // fails harder: as expected
  const auto comparison = CompareRuns(Passing(), candidate, Tolerances());
  EXPECT_FALSE(comparison.worse());
  EXPECT_EQ(Check(comparison, "ablated").change(), proto::SAME);
}

TEST(CompareRunsTest, ALostEnvelopeIsWorseANewOneIsNot) {
  proto::Report candidate = Passing();
  candidate.mutable_envelopes()->DeleteSubrange(1, 1);
  AddEnvelope(candidate, "new_check", false, -1);
  const auto comparison = CompareRuns(Passing(), candidate, Tolerances());
  EXPECT_EQ(Check(comparison, "altitude_error").change(), proto::ONLY_IN_BASE);
  EXPECT_EQ(Check(comparison, "new_check").change(), proto::ONLY_IN_CANDIDATE);
  ASSERT_EQ(comparison.reason_size(), 1);
  EXPECT_THAT(comparison.reason(0), HasSubstr("altitude_error: in the base, missing from"));
}

TEST(CompareRunsTest, ATargetCheckThatNoLongerPassesIsWorse) {
  proto::Report base = Passing();
  auto* check = base.add_target_checks();
  check->set_name("work_p99_fraction_max");
  check->set_evaluated(true);
  check->set_passed(true);
  check->set_value(0.02);
  proto::Report candidate = base;
  candidate.mutable_target_checks(0)->set_passed(false);
  candidate.mutable_target_checks(0)->set_value(0.7);
  const auto comparison = CompareRuns(base, candidate, Tolerances());
  EXPECT_TRUE(comparison.worse());
  const auto& row = Check(comparison, "work_p99_fraction_max");
  EXPECT_EQ(row.kind(), proto::CheckChange::TARGET);
  EXPECT_EQ(row.change(), proto::WORSE);
  EXPECT_DOUBLE_EQ(row.candidate_worst(), 0.7);
  EXPECT_THAT(comparison.reason(0), HasSubstr("target check work_p99_fraction_max"));
}

// Runs that did not complete proved nothing: comparing them is never "not worse", even when both
// stopped the same way.
TEST(CompareRunsTest, TwoIncompleteRunsAreNotNotWorse) {
  proto::Report incomplete = Passing();
  incomplete.set_passed(false);
  incomplete.set_stop_kind(proto::STOP_INCOMPLETE);
  incomplete.set_stop_reason("incomplete");
  const auto comparison = CompareRuns(incomplete, incomplete, Tolerances());
  EXPECT_TRUE(comparison.worse());
  EXPECT_THAT(comparison.reason(), ::testing::Contains(HasSubstr("the base run did not complete")));
  EXPECT_THAT(comparison.reason(),
              ::testing::Contains(HasSubstr("the candidate run did not complete (incomplete)")));
}

TEST(CompareRunsTest, AnEnvelopeNotEvaluatedInTheCandidateIsWorse) {
  // Both runs cut short the same way: the same verdicts, and still nothing proved.
  proto::Report cut = Passing();
  cut.mutable_envelopes(1)->set_not_evaluated(true);
  cut.mutable_envelopes(1)->set_meets_expectation(false);
  const auto comparison = CompareRuns(cut, cut, Tolerances());
  EXPECT_TRUE(comparison.worse());
  EXPECT_THAT(comparison.reason(),
              ::testing::Contains(HasSubstr("envelope altitude_error: not evaluated")));
}

}  // namespace
}  // namespace hilrig::host
