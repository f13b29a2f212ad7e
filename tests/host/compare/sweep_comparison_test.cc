// Two sweep summaries compared: the Fisher exact lower tail against hand-computed values, a pass
// rate that fell significantly against one that fell by chance, margin quantiles gated by the
// cases under them, a lost criterion, a lost envelope and an incomplete candidate.
#include "host/compare/sweep_comparison.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

TEST(FisherLowerTailTest, MatchesTheHypergeometricByHand) {
  // 10/10 against 0/10: only the table seen, 1 / C(20, 10).
  EXPECT_NEAR(FisherLowerTail(10, 10, 0, 10), 1.0 / 184756, 1e-15);
  // 1/2 against 0/2: C(3, 2) / C(4, 2).
  EXPECT_NEAR(FisherLowerTail(1, 2, 0, 2), 0.5, 1e-12);
  // 5/5 against 4/5: C(9, 4) / C(10, 5).
  EXPECT_NEAR(FisherLowerTail(5, 5, 4, 5), 0.5, 1e-12);
  // No drop at all: more than half of the distribution lies at or below it.
  EXPECT_GT(FisherLowerTail(7, 10, 7, 10), 0.5);
  EXPECT_NEAR(FisherLowerTail(0, 10, 0, 10), 1.0, 1e-12);
  EXPECT_EQ(FisherLowerTail(3, 0, 1, 4), 1.0);
  EXPECT_EQ(FisherLowerTail(3, 4, 1, 0), 1.0);
  // Large sweeps stay finite and small: 1000/1000 against 990/1000.
  const double p = FisherLowerTail(1000, 1000, 990, 1000);
  EXPECT_GT(p, 0);
  EXPECT_LT(p, 0.01);
}

proto::SweepEnvelopeStats* AddStats(proto::SweepSummary& summary, const std::string& envelope,
                                    std::uint64_t met, std::uint64_t cases) {
  auto* stats = summary.add_envelope();
  stats->set_scenario("balloon_grasp");
  stats->set_envelope(envelope);
  stats->set_met(met);
  stats->set_cases(cases);
  stats->set_pass_rate(static_cast<double>(met) / static_cast<double>(cases));
  stats->set_margins(cases);
  stats->mutable_margin()->set_min(0.01);
  stats->mutable_margin()->set_q01(0.01);
  stats->mutable_margin()->set_q10(0.02);
  stats->mutable_margin()->set_q50(0.04);
  return stats;
}

proto::SweepSummary Summary(std::uint64_t met, std::uint64_t cases) {
  proto::SweepSummary summary;
  summary.set_sweep("balloon_seeds");
  summary.set_cases(cases);
  summary.set_sweep_cases(cases);
  AddStats(summary, "grasp_force", met, cases);
  auto* check = summary.add_check();
  check->set_scenario("balloon_grasp");
  check->set_envelope("grasp_force");
  check->set_passed(met == cases);
  return summary;
}

proto::CompareTolerances Tolerances() {
  proto::CompareTolerances tolerances;
  tolerances.set_margin_fraction(0.1);
  tolerances.set_confidence(0.95);
  return tolerances;
}

TEST(CompareSweepsTest, TheSameSummaryIsNotWorse) {
  const auto comparison = CompareSweeps(Summary(100, 100), Summary(100, 100), Tolerances());
  EXPECT_FALSE(comparison.worse());
  ASSERT_EQ(comparison.envelope_size(), 1);
  EXPECT_EQ(comparison.envelope(0).change(), proto::SAME);
  EXPECT_NEAR(comparison.envelope(0).p_value(), 1, 1e-9);
  ASSERT_EQ(comparison.envelope(0).quantile_size(), 4);
  EXPECT_EQ(comparison.criterion(0).change(), proto::SAME);
}

TEST(CompareSweepsTest, ASignificantDropIsWorseAChanceOneIsNot) {
  proto::SweepSummary base = Summary(100, 100);
  base.mutable_check(0)->set_passed(false);  // keep the criterion out of this test
  proto::SweepSummary chance = Summary(99, 100);
  chance.mutable_check(0)->set_passed(false);
  const auto small = CompareSweeps(base, chance, Tolerances());
  EXPECT_EQ(small.envelope(0).change(), proto::WORSE_WITHIN_TOLERANCE);
  EXPECT_GT(small.envelope(0).p_value(), 0.05);
  EXPECT_FALSE(small.worse());
  proto::SweepSummary drop = Summary(80, 100);
  drop.mutable_check(0)->set_passed(false);
  const auto large = CompareSweeps(base, drop, Tolerances());
  EXPECT_EQ(large.envelope(0).change(), proto::WORSE);
  EXPECT_LT(large.envelope(0).p_value(), 1e-5);
  ASSERT_TRUE(large.worse());
  EXPECT_THAT(large.reason(0), HasSubstr("balloon_grasp/grasp_force: the pass rate fell"));
  // A tolerance of 25 points lets the same drop through.
  proto::CompareTolerances loose = Tolerances();
  loose.set_pass_rate_drop(0.25);
  EXPECT_FALSE(CompareSweeps(base, drop, loose).worse());
}

TEST(CompareSweepsTest, OnlyQuantilesWithEnoughCasesUnderThemGate) {
  proto::SweepSummary candidate = Summary(100, 100);
  candidate.mutable_envelope(0)->mutable_margin()->set_min(-0.5);  // one case: not gated
  candidate.mutable_envelope(0)->mutable_margin()->set_q01(0.0);   // 1 case under it: not gated
  auto comparison = CompareSweeps(Summary(100, 100), candidate, Tolerances());
  EXPECT_FALSE(comparison.worse());
  EXPECT_FALSE(comparison.envelope(0).quantile(0).gated());
  EXPECT_EQ(comparison.envelope(0).quantile(0).change(), proto::WORSE);
  EXPECT_FALSE(comparison.envelope(0).quantile(1).gated());
  EXPECT_TRUE(comparison.envelope(0).quantile(2).gated());          // q10 of 100: 10 cases
  candidate.mutable_envelope(0)->mutable_margin()->set_q10(0.015);  // 25 % less room
  comparison = CompareSweeps(Summary(100, 100), candidate, Tolerances());
  ASSERT_TRUE(comparison.worse());
  EXPECT_THAT(comparison.reason(0), HasSubstr("the margin's q10 shrank beyond the tolerance"));
}

// An ablation's envelope has no room to lose, as in a run's comparison: a margin further outside
// the bounds is not worse, and only the pass rate (failing as expected) is graded.
TEST(CompareSweepsTest, AnEnvelopeExpectedToFailIsGradedByItsPassRateAlone) {
  proto::SweepSummary base = Summary(100, 100);
  base.mutable_envelope(0)->set_expected_fail(true);
  base.mutable_envelope(0)->mutable_margin()->set_q10(-0.2);
  proto::SweepSummary candidate = base;
  candidate.mutable_envelope(0)->mutable_margin()->set_q10(-0.4);
  const auto further_out = CompareSweeps(base, candidate, Tolerances());
  EXPECT_FALSE(further_out.worse());
  EXPECT_TRUE(further_out.envelope(0).expected_fail());
  EXPECT_EQ(further_out.envelope(0).quantile_size(), 0);
  // The same margins on an envelope expected to pass: the q10 lost all its room.
  base.mutable_envelope(0)->set_expected_fail(false);
  candidate.mutable_envelope(0)->set_expected_fail(false);
  EXPECT_TRUE(CompareSweeps(base, candidate, Tolerances()).worse());
  // An ablation that stops failing loses its pass rate.
  base.mutable_envelope(0)->set_expected_fail(true);
  candidate = Summary(0, 100);
  candidate.mutable_envelope(0)->set_expected_fail(true);
  candidate.mutable_check(0)->set_passed(true);
  const auto stopped_failing = CompareSweeps(base, candidate, Tolerances());
  EXPECT_EQ(stopped_failing.envelope(0).change(), proto::WORSE);
  EXPECT_TRUE(stopped_failing.worse());
}

TEST(CompareSweepsTest, ALostCriterionOrEnvelopeOrAnUnfinishedSweepIsWorse) {
  proto::SweepSummary base = Summary(100, 100);
  AddStats(base, "altitude_error", 100, 100);
  proto::SweepSummary candidate = Summary(100, 100);
  candidate.mutable_check(0)->set_passed(false);
  candidate.set_cases(60);
  const auto comparison = CompareSweeps(base, candidate, Tolerances());
  ASSERT_TRUE(comparison.worse());
  ASSERT_EQ(comparison.reason_size(), 3);
  EXPECT_THAT(comparison.reason(0), HasSubstr("the candidate sweep is incomplete: 60 of 100"));
  EXPECT_THAT(comparison.reason(1), HasSubstr("altitude_error: in the base sweep, missing"));
  EXPECT_THAT(comparison.reason(2), HasSubstr("criterion[0] (balloon_grasp/grasp_force): met in"));
  EXPECT_EQ(comparison.envelope(1).change(), proto::ONLY_IN_BASE);
  EXPECT_EQ(comparison.criterion(0).change(), proto::WORSE);
}

}  // namespace
}  // namespace hilrig::host
