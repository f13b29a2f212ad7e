// A sweep's statistics: the normal quantile and the Wilson interval against known values, nearest
// rank with NaNs set apart, the per-envelope tally (cases that did not run cannot pass and give no
// margin), the criteria's checks on the low tail of the margin, and a JSON that depends on the set
// of results alone.
#include "host/sweep/sweep_statistics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::Not;
using Outcome = proto::SweepCaseResult::Outcome;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(StandardNormalQuantileTest, MatchesKnownValues) {
  EXPECT_NEAR(StandardNormalQuantile(0.975), 1.959963984540054, 1e-12);
  EXPECT_NEAR(StandardNormalQuantile(0.995), 2.5758293035489, 1e-12);
  EXPECT_NEAR(StandardNormalQuantile(0.8), 0.8416212335729143, 1e-12);
  EXPECT_NEAR(StandardNormalQuantile(0.025), -1.959963984540054, 1e-12);
  EXPECT_NEAR(StandardNormalQuantile(0.5), 0.0, 1e-15);
  // Both sides of the switch to the tail approximation, and deep in the tail.
  EXPECT_NEAR(StandardNormalQuantile(0.02425), -1.9729610513118845, 1e-12);
  EXPECT_NEAR(StandardNormalQuantile(1e-10), -6.361340902404056, 1e-11);
  EXPECT_NEAR(StandardNormalQuantile(1e-300), -37.0470962993612, 1e-10);
}

TEST(StandardNormalQuantileTest, EndsAreInfiniteAndNanStaysNan) {
  EXPECT_EQ(StandardNormalQuantile(0), -kInf);
  EXPECT_EQ(StandardNormalQuantile(-0.5), -kInf);
  EXPECT_EQ(StandardNormalQuantile(1), kInf);
  EXPECT_TRUE(std::isnan(StandardNormalQuantile(kNan)));
}

TEST(WilsonIntervalTest, MatchesTheFormula) {
  const WilsonBounds ninety_five = WilsonInterval(95, 100, 0.95);
  EXPECT_NEAR(ninety_five.lower, 0.8882495307680808, 1e-12);
  EXPECT_NEAR(ninety_five.upper, 0.9784563208456319, 1e-12);
  const WilsonBounds half = WilsonInterval(50, 100, 0.99);
  EXPECT_NEAR(half.lower, 0.37527962504483986, 1e-12);
  EXPECT_NEAR(half.upper, 0.6247203749551602, 1e-12);
  const WilsonBounds third = WilsonInterval(1, 3, 0.8);
  EXPECT_NEAR(third.lower, 0.10577563612172286, 1e-12);
  EXPECT_NEAR(third.upper, 0.6788173521696517, 1e-12);
}

TEST(WilsonIntervalTest, NoneAndAllSuccessesReachTheEndsExactly) {
  const WilsonBounds none = WilsonInterval(0, 20, 0.95);
  EXPECT_EQ(none.lower, 0.0);
  EXPECT_NEAR(none.upper, 0.1611251580528193, 1e-12);
  const WilsonBounds all = WilsonInterval(20, 20, 0.95);
  EXPECT_NEAR(all.lower, 0.8388748419471808, 1e-12);
  EXPECT_EQ(all.upper, 1.0);
}

TEST(WilsonIntervalTest, DegenerateInputsGiveTheObviousInterval) {
  const WilsonBounds no_trials = WilsonInterval(0, 0, 0.95);
  EXPECT_EQ(no_trials.lower, 0.0);
  EXPECT_EQ(no_trials.upper, 1.0);
  const WilsonBounds point = WilsonInterval(3, 4, 0);
  EXPECT_EQ(point.lower, 0.75);
  EXPECT_EQ(point.upper, 0.75);
  const WilsonBounds certain = WilsonInterval(3, 4, 1);
  EXPECT_EQ(certain.lower, 0.0);
  EXPECT_EQ(certain.upper, 1.0);
  const WilsonBounds too_many = WilsonInterval(30, 20, 0.95);
  EXPECT_EQ(too_many.upper, 1.0);
  EXPECT_EQ(too_many.lower, WilsonInterval(20, 20, 0.95).lower);
}

TEST(NearestRankQuantileTest, SmallestValueWithAtLeastQAtOrBelowIt) {
  const std::vector<double> values = {5, 1, 4, 2, 3};
  EXPECT_EQ(NearestRankQuantile(values, 0), 1.0);
  EXPECT_EQ(NearestRankQuantile(values, 0.2), 1.0);
  EXPECT_EQ(NearestRankQuantile(values, 0.21), 2.0);
  EXPECT_EQ(NearestRankQuantile(values, 0.5), 3.0);
  EXPECT_EQ(NearestRankQuantile(values, 0.8), 4.0);
  EXPECT_EQ(NearestRankQuantile(values, 1), 5.0);
  EXPECT_EQ(NearestRankQuantile(values, -1), 1.0);
  EXPECT_EQ(NearestRankQuantile(values, 2), 5.0);
  EXPECT_EQ(NearestRankQuantile(values, kNan), 1.0);
  EXPECT_EQ(NearestRankQuantile({}, 0.5), std::nullopt);
}

TEST(NearestRankQuantileTest, ADecimalQuantileTakesTheRankAsWritten) {
  std::vector<double> one_to_hundred;
  for (int i = 1; i <= 100; ++i) one_to_hundred.push_back(i);
  const SortedSample sample(one_to_hundred);
  // 0.07 * 100 is 7.000000000000001 in binary: a plain ceil would take the 8th value.
  EXPECT_EQ(sample.Quantile(0.07), 7.0);
  EXPECT_EQ(sample.Quantile(0.55), 55.0);
  EXPECT_EQ(sample.Quantile(0.071), 8.0);
  EXPECT_EQ(sample.Quantile(0.29), 29.0);
}

TEST(SortedSampleTest, NansAreSetApartAndCountedInfinitiesKept) {
  const SortedSample sample({kNan, 3, kNan, -kInf, 1});
  EXPECT_EQ(sample.size(), 3u);
  EXPECT_EQ(sample.nan_count(), 2u);
  EXPECT_EQ(sample.Quantile(0), -kInf);
  EXPECT_EQ(sample.Quantile(0.5), 1.0);
  EXPECT_EQ(sample.Quantile(1), 3.0);
  const SortedSample only_nans({kNan, kNan});
  EXPECT_EQ(only_nans.size(), 0u);
  EXPECT_EQ(only_nans.nan_count(), 2u);
  EXPECT_EQ(only_nans.Quantile(0.5), std::nullopt);
}

// Scenario "a" with envelopes "not_dropped" and "clearance", scenario "b" with "not_dropped".
LoadedSweep TwoScenarios() {
  LoadedSweep sweep;
  sweep.spec.set_name("grasp_sweep");
  for (const auto& [name, envelopes] :
       std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"a", {"not_dropped", "clearance"}}, {"b", {"not_dropped"}}}) {
    SweepScenario& scenario = sweep.scenarios.emplace_back();
    scenario.path = name + ".textproto";
    scenario.spec.set_name(name);
    for (const std::string& envelope : envelopes) scenario.spec.add_envelopes()->set_name(envelope);
  }
  return sweep;
}

struct EnvelopeRecord {
  std::string name;
  bool met;
  double margin;
};

proto::SweepCaseResult Case(const std::string& scenario, Outcome outcome,
                            const std::vector<EnvelopeRecord>& envelopes) {
  static std::uint64_t index = 0;
  proto::SweepCaseResult result;
  result.set_index(index++);
  result.set_scenario(scenario);
  result.set_outcome(outcome);
  for (const EnvelopeRecord& record : envelopes) {
    proto::SweepCaseResult::Envelope* envelope = result.add_envelope();
    envelope->set_name(record.name);
    envelope->set_met(record.met);
    envelope->set_margin(record.margin);
    envelope->set_worst(-record.margin);
  }
  return result;
}

// `cases` cases of scenario "a" that ran, with "not_dropped" met in the first `met` and margins
// `margin(i)` on both envelopes.
std::vector<proto::SweepCaseResult> CasesOfA(int cases, int met,
                                             const std::function<double(int)>& margin) {
  std::vector<proto::SweepCaseResult> results;
  for (int i = 0; i < cases; ++i) {
    results.push_back(
        Case("a", i < met ? proto::SweepCaseResult::PASSED : proto::SweepCaseResult::FAILED,
             {{"not_dropped", i < met, margin(i)}, {"clearance", true, margin(i)}}));
  }
  return results;
}

const EnvelopeTally& Tally(const SweepTally& tally, const std::string& scenario,
                           const std::string& envelope) {
  const auto found =
      std::find_if(tally.envelopes.begin(), tally.envelopes.end(), [&](const EnvelopeTally& t) {
        return t.stats.scenario() == scenario && t.stats.envelope() == envelope;
      });
  EXPECT_NE(found, tally.envelopes.end()) << scenario << "/" << envelope;
  return *found;
}

TEST(TallySweepTest, ListsEveryEnvelopeInTheSweepsOrderWithPassRateAndInterval) {
  const SweepTally tally =
      TallySweep(TwoScenarios(), CasesOfA(100, 95, [](int i) { return i * 1.0; }));
  ASSERT_EQ(tally.envelopes.size(), 3u);
  EXPECT_EQ(tally.envelopes[0].stats.envelope(), "not_dropped");
  EXPECT_EQ(tally.envelopes[1].stats.envelope(), "clearance");
  EXPECT_EQ(tally.envelopes[2].stats.scenario(), "b");
  EXPECT_EQ(tally.cases, 100u);
  const proto::SweepEnvelopeStats& stats = tally.envelopes[0].stats;
  EXPECT_EQ(stats.cases(), 100u);
  EXPECT_EQ(stats.met(), 95u);
  EXPECT_DOUBLE_EQ(stats.pass_rate(), 0.95);
  EXPECT_NEAR(stats.pass_rate_lower(), 0.8882495307680808, 1e-12);
  EXPECT_NEAR(stats.pass_rate_upper(), 0.9784563208456319, 1e-12);
  EXPECT_EQ(stats.outcomes().passed(), 95u);
  EXPECT_EQ(stats.outcomes().failed(), 5u);
  EXPECT_EQ(tally.envelopes[1].stats.met(), 100u);
  // Scenario "b" had no case: listed, nothing known.
  const proto::SweepEnvelopeStats& b = tally.envelopes[2].stats;
  EXPECT_EQ(b.cases(), 0u);
  EXPECT_EQ(b.pass_rate_lower(), 0.0);
  EXPECT_EQ(b.pass_rate_upper(), 1.0);
  EXPECT_FALSE(b.has_margin());
}

TEST(TallySweepTest, MarginQuantilesAreTheLowTail) {
  // Margins 100, 99, ..., 1: the order of the results must not matter.
  const SweepTally tally =
      TallySweep(TwoScenarios(), CasesOfA(100, 100, [](int i) { return 100.0 - i; }));
  const proto::SweepEnvelopeStats& stats = Tally(tally, "a", "clearance").stats;
  EXPECT_EQ(stats.margins(), 100u);
  ASSERT_TRUE(stats.has_margin());
  EXPECT_EQ(stats.margin().min(), 1.0);
  EXPECT_EQ(stats.margin().q01(), 1.0);
  EXPECT_EQ(stats.margin().q10(), 10.0);
  EXPECT_EQ(stats.margin().q50(), 50.0);
}

TEST(TallySweepTest, CasesThatDidNotRunMeetNoEnvelopeAndGiveNoMargin) {
  std::vector<proto::SweepCaseResult> results = CasesOfA(2, 2, [](int) { return 1.0; });
  // A stopped case may carry envelope records; they are not a verdict and not a margin.
  results.push_back(Case("a", proto::SweepCaseResult::STOPPED, {{"not_dropped", true, -50}}));
  results.push_back(Case("a", proto::SweepCaseResult::INVALID, {}));
  results.push_back(Case("a", proto::SweepCaseResult::SET_UP_FAILED, {}));
  results.push_back(Case("a", proto::SweepCaseResult::OUTCOME_UNSPECIFIED, {}));
  const SweepTally tally = TallySweep(TwoScenarios(), results);
  for (const char* envelope : {"not_dropped", "clearance"}) {
    const EnvelopeTally& tallied = Tally(tally, "a", envelope);
    const proto::SweepEnvelopeStats& stats = tallied.stats;
    EXPECT_EQ(stats.cases(), 6u) << envelope;
    EXPECT_EQ(stats.met(), 2u) << envelope;
    EXPECT_EQ(stats.not_run(), 4u) << envelope;
    EXPECT_EQ(stats.unrecorded(), 0u) << envelope;
    EXPECT_DOUBLE_EQ(stats.pass_rate(), 2.0 / 6) << envelope;
    EXPECT_EQ(stats.margins(), 2u) << envelope;
    EXPECT_EQ(stats.margin().min(), 1.0) << envelope;
    EXPECT_EQ(tallied.margins.size(), 2u) << envelope;
    EXPECT_EQ(stats.outcomes().passed(), 2u);
    EXPECT_EQ(stats.outcomes().stopped(), 1u);
    EXPECT_EQ(stats.outcomes().invalid(), 1u);
    EXPECT_EQ(stats.outcomes().set_up_failed(), 1u);
    EXPECT_EQ(stats.outcomes().unspecified(), 1u);
  }
}

TEST(TallySweepTest, UnknownScenariosMissingRecordsAndNanMarginsAreCountedApart) {
  const std::vector<proto::SweepCaseResult> results = {
      Case("zzz", proto::SweepCaseResult::PASSED, {{"not_dropped", true, 1}}),
      // No record of "clearance": it ran, so it counts, but it cannot pass.
      Case("a", proto::SweepCaseResult::PASSED, {{"not_dropped", true, 2}}),
      // A NaN margin has no rank; the verdict still counts. A repeated record counts once.
      Case("a", proto::SweepCaseResult::PASSED,
           {{"not_dropped", true, kNan}, {"clearance", true, 3}, {"clearance", false, -9}}),
      // An envelope the scenario does not have is left out.
      Case("b", proto::SweepCaseResult::PASSED, {{"not_dropped", true, 4}, {"other", true, 5}}),
  };
  const SweepTally tally = TallySweep(TwoScenarios(), results);
  EXPECT_EQ(tally.cases, 4u);
  EXPECT_EQ(tally.unknown_cases, 1u);
  const proto::SweepEnvelopeStats& not_dropped = Tally(tally, "a", "not_dropped").stats;
  EXPECT_EQ(not_dropped.met(), 2u);
  EXPECT_EQ(not_dropped.margins(), 1u);
  EXPECT_EQ(not_dropped.nan_margins(), 1u);
  EXPECT_EQ(not_dropped.margin().min(), 2.0);
  const proto::SweepEnvelopeStats& clearance = Tally(tally, "a", "clearance").stats;
  EXPECT_EQ(clearance.cases(), 2u);
  EXPECT_EQ(clearance.met(), 1u);
  EXPECT_EQ(clearance.unrecorded(), 1u);
  EXPECT_EQ(clearance.margins(), 1u);
  EXPECT_EQ(clearance.margin().min(), 3.0);
  EXPECT_EQ(Tally(tally, "b", "not_dropped").stats.met(), 1u);
  EXPECT_EQ(tally.envelopes.size(), 3u);
}

TEST(TallySweepTest, ScenariosSharingANamePoolTheirEnvelopes) {
  LoadedSweep sweep = TwoScenarios();
  SweepScenario& again = sweep.scenarios.emplace_back();
  again.spec.set_name("a");
  again.spec.add_envelopes()->set_name("clearance");
  again.spec.add_envelopes()->set_name("settled");
  const SweepTally tally = TallySweep(sweep, CasesOfA(3, 3, [](int) { return 1.0; }));
  std::vector<std::string> listed;
  for (const EnvelopeTally& t : tally.envelopes) {
    listed.push_back(t.stats.scenario() + "/" + t.stats.envelope());
  }
  EXPECT_THAT(listed, ElementsAre("a/not_dropped", "a/clearance", "b/not_dropped", "a/settled"));
  EXPECT_EQ(Tally(tally, "a", "clearance").stats.cases(), 3u);
  EXPECT_EQ(Tally(tally, "a", "settled").stats.unrecorded(), 3u);
}

proto::Criterion PassRate(const std::string& envelope, double min_pass_rate) {
  proto::Criterion criterion;
  criterion.set_envelope(envelope);
  criterion.set_min_pass_rate(min_pass_rate);
  return criterion;
}

proto::Criterion MarginAt(const std::string& envelope, double quantile, double min_margin) {
  proto::Criterion criterion;
  criterion.set_envelope(envelope);
  criterion.set_scenario("a");
  criterion.set_quantile(quantile);
  criterion.set_min_margin(min_margin);
  return criterion;
}

std::vector<proto::SweepCriterionCheck> Grade(const std::vector<proto::Criterion>& criteria,
                                              const std::vector<proto::SweepCaseResult>& results) {
  LoadedSweep sweep = TwoScenarios();
  for (const proto::Criterion& criterion : criteria) *sweep.spec.add_criterion() = criterion;
  return GradeCriteria(sweep.spec, TallySweep(sweep, results).envelopes);
}

TEST(GradeCriteriaTest, PassRateIsShownByTheWilsonLowerBound) {
  proto::Criterion at_99 = PassRate("not_dropped", 0.87);
  at_99.set_scenario("a");
  at_99.set_confidence(0.99);
  proto::Criterion strict = PassRate("not_dropped", 0.9);
  strict.set_scenario("a");
  proto::Criterion loose = strict;
  loose.set_min_pass_rate(0.88);
  const auto checks = Grade({loose, strict, at_99}, CasesOfA(100, 95, [](int) { return 1.0; }));
  ASSERT_EQ(checks.size(), 3u);
  EXPECT_EQ(checks[0].kind(), proto::SweepCriterionCheck::PASS_RATE);
  EXPECT_EQ(checks[0].criterion(), 0u);
  EXPECT_EQ(checks[0].scenario(), "a");
  EXPECT_EQ(checks[0].envelope(), "not_dropped");
  EXPECT_NEAR(checks[0].measured(), 0.8882495307680808, 1e-12);
  EXPECT_EQ(checks[0].limit(), 0.88);
  EXPECT_TRUE(checks[0].passed());
  EXPECT_THAT(checks[0].note(), HasSubstr("95 of 100"));
  // 95 % met, but 100 cases do not show 90 % at 95 % confidence.
  EXPECT_FALSE(checks[1].passed());
  EXPECT_EQ(checks[1].criterion(), 1u);
  // More confidence asks for a lower bound further down: 87 % is shown at 95 % but not at 99 %.
  EXPECT_NEAR(checks[2].measured(), 0.8608496970983599, 1e-12);
  EXPECT_FALSE(checks[2].passed());
  EXPECT_THAT(checks[2].note(), HasSubstr("99 % confidence"));
}

TEST(GradeCriteriaTest, MarginQuantileReadsTheLowTail) {
  // 100 cases; the first `negative` of them end outside the bounds.
  const auto margins = [](int negative) {
    return CasesOfA(100, 100, [negative](int i) { return i < negative ? -1.0 - i : 0.5 + i; });
  };
  const proto::Criterion five_percent = MarginAt("clearance", 0.05, 0);
  const auto four_out = Grade({five_percent}, margins(4));
  ASSERT_EQ(four_out.size(), 1u);
  EXPECT_EQ(four_out[0].kind(), proto::SweepCriterionCheck::MARGIN_QUANTILE);
  EXPECT_EQ(four_out[0].measured(), 4.5);  // the 5th smallest
  EXPECT_TRUE(four_out[0].passed());
  const auto five_out = Grade({five_percent}, margins(5));
  EXPECT_EQ(five_out[0].measured(), -1.0);
  EXPECT_FALSE(five_out[0].passed());
  // Quantile 0: every case that ran must keep the margin.
  const auto one_out =
      Grade({MarginAt("clearance", 0, 0), MarginAt("clearance", 0, -2)}, margins(1));
  ASSERT_EQ(one_out.size(), 2u);
  EXPECT_EQ(one_out[0].measured(), -1.0);
  EXPECT_FALSE(one_out[0].passed());
  EXPECT_EQ(one_out[1].limit(), -2.0);
  EXPECT_TRUE(one_out[1].passed());
}

TEST(GradeCriteriaTest, CasesThatDidNotRunLowerThePassRateNotTheMargin) {
  std::vector<proto::SweepCaseResult> results = CasesOfA(10, 10, [](int) { return 1.0; });
  for (int i = 0; i < 10; ++i) results.push_back(Case("a", proto::SweepCaseResult::STOPPED, {}));
  proto::Criterion criterion = MarginAt("clearance", 0, 0);
  criterion.set_min_pass_rate(0.6);
  const auto checks = Grade({criterion}, results);
  ASSERT_EQ(checks.size(), 2u);
  EXPECT_EQ(checks[0].kind(), proto::SweepCriterionCheck::PASS_RATE);
  EXPECT_EQ(checks[0].measured(), WilsonInterval(10, 20, 0.95).lower);
  EXPECT_FALSE(checks[0].passed());
  EXPECT_EQ(checks[1].measured(), 1.0);
  EXPECT_TRUE(checks[1].passed());
}

TEST(GradeCriteriaTest, EmptyNamesMatchEveryScenarioAndEveryEnvelope) {
  proto::Criterion every;
  every.set_min_pass_rate(0.1);
  proto::Criterion of_a = every;
  of_a.set_scenario("a");
  const auto checks =
      Grade({every, PassRate("not_dropped", 0.1), of_a}, CasesOfA(10, 10, [](int) { return 1.0; }));
  std::vector<std::string> checked;
  for (const proto::SweepCriterionCheck& check : checks) {
    checked.push_back(std::to_string(check.criterion()) + ":" + check.scenario() + "/" +
                      check.envelope());
  }
  EXPECT_THAT(checked,
              ElementsAre("0:a/not_dropped", "0:a/clearance", "0:b/not_dropped", "1:a/not_dropped",
                          "1:b/not_dropped", "2:a/not_dropped", "2:a/clearance"));
}

TEST(GradeCriteriaTest, NothingMeasuredFailsWithANote) {
  proto::Criterion of_b = PassRate("not_dropped", 0);
  of_b.set_scenario("b");
  of_b.set_quantile(0.5);
  proto::Criterion of_a = MarginAt("clearance", 0.5, -100);
  of_a.set_min_pass_rate(0);
  const std::vector<proto::SweepCaseResult> invalid = {
      Case("a", proto::SweepCaseResult::INVALID, {}),
      Case("a", proto::SweepCaseResult::INVALID, {}),
  };
  const auto checks = Grade({of_b, of_a}, invalid);
  ASSERT_EQ(checks.size(), 4u);
  for (const proto::SweepCriterionCheck& check : checks) {
    EXPECT_FALSE(check.passed()) << check.ShortDebugString();
  }
  EXPECT_FALSE(checks[0].has_measured());
  EXPECT_THAT(checks[0].note(), HasSubstr("no case"));
  EXPECT_FALSE(checks[1].has_measured());
  // Scenario "a" has cases, none of which ran: the pass rate is measured (0) yet proves nothing.
  EXPECT_EQ(checks[2].measured(), 0.0);
  EXPECT_THAT(checks[2].note(), HasSubstr("none of the 2 cases ran"));
  EXPECT_FALSE(checks[3].has_measured());
}

TEST(GradeCriteriaTest, ACriterionMatchingNoEnvelopeFails) {
  proto::Criterion criterion = PassRate("clearance", 0.5);
  criterion.set_scenario("b");
  criterion.set_quantile(0.1);
  const auto checks = Grade({criterion}, CasesOfA(10, 10, [](int) { return 1.0; }));
  ASSERT_EQ(checks.size(), 2u);
  EXPECT_EQ(checks[0].kind(), proto::SweepCriterionCheck::PASS_RATE);
  EXPECT_EQ(checks[1].kind(), proto::SweepCriterionCheck::MARGIN_QUANTILE);
  for (const proto::SweepCriterionCheck& check : checks) {
    EXPECT_FALSE(check.passed());
    EXPECT_EQ(check.scenario(), "b");
    EXPECT_EQ(check.envelope(), "clearance");
    EXPECT_THAT(check.note(), HasSubstr("no envelope"));
  }
}

// Scenario "a"'s "clearance" as an ablation's envelope: expected to fail, met when it fails, and
// its margin negative whenever it is met.
TEST(GradeCriteriaTest, AMarginCriterionPassesOverEnvelopesExpectedToFail) {
  LoadedSweep sweep = TwoScenarios();
  sweep.scenarios[0].spec.mutable_envelopes(1)->set_expect(proto::FAIL);
  proto::Criterion every;
  every.set_quantile(0.5);
  every.set_min_pass_rate(0.5);
  *sweep.spec.add_criterion() = every;
  const SweepTally tally = TallySweep(sweep, CasesOfA(10, 10, [](int) { return -0.25; }));
  EXPECT_TRUE(Tally(tally, "a", "clearance").stats.expected_fail());
  EXPECT_FALSE(Tally(tally, "a", "not_dropped").stats.expected_fail());
  std::vector<std::string> checked;
  for (const proto::SweepCriterionCheck& check : GradeCriteria(sweep.spec, tally.envelopes)) {
    checked.push_back(check.scenario() + "/" + check.envelope() + ":" +
                      proto::SweepCriterionCheck::Kind_Name(check.kind()) + ":" +
                      (check.passed() ? "passed" : "failed"));
  }
  // "clearance" is graded by its pass rate alone; "not_dropped" is expected to pass, and its
  // margin of -0.25 fails it.
  EXPECT_THAT(checked,
              ElementsAre("a/not_dropped:PASS_RATE:passed", "a/not_dropped:MARGIN_QUANTILE:failed",
                          "a/clearance:PASS_RATE:passed", "b/not_dropped:PASS_RATE:failed",
                          "b/not_dropped:MARGIN_QUANTILE:failed"));
}

TEST(SummariseSweepTest, PassesOnlyWhenEveryCheckPasses) {
  LoadedSweep sweep = TwoScenarios();
  proto::Criterion of_a = PassRate("", 0.8);
  of_a.set_scenario("a");
  *sweep.spec.add_criterion() = of_a;
  const auto results = CasesOfA(100, 100, [](int) { return 1.0; });
  const proto::SweepSummary passing = SummariseSweep(sweep, results);
  EXPECT_EQ(passing.sweep(), "grasp_sweep");
  EXPECT_EQ(passing.cases(), 100u);
  EXPECT_EQ(passing.envelope_size(), 3);
  EXPECT_EQ(passing.check_size(), 2);
  EXPECT_TRUE(passing.passed());
  // Scenario "b" never ran: a criterion over it fails the sweep.
  *sweep.spec.add_criterion() = PassRate("not_dropped", 0.8);
  const proto::SweepSummary failing = SummariseSweep(sweep, results);
  EXPECT_EQ(failing.check_size(), 4);
  EXPECT_FALSE(failing.passed());
  sweep.spec.clear_criterion();
  EXPECT_FALSE(SummariseSweep(sweep, results).passed());
}

TEST(SummaryJsonTest, DependsOnTheSetOfResultsAloneNotTheirOrderOrTiming) {
  LoadedSweep sweep = TwoScenarios();
  proto::Criterion criterion = MarginAt("clearance", 0.05, 0);
  criterion.set_min_pass_rate(0.5);
  *sweep.spec.add_criterion() = criterion;
  *sweep.spec.add_criterion() = PassRate("not_dropped", 0.5);
  std::vector<proto::SweepCaseResult> results =
      CasesOfA(50, 40, [](int i) { return std::sin(i) * 3; });
  results.push_back(Case("a", proto::SweepCaseResult::STOPPED, {}));
  std::vector<proto::SweepCaseResult> elsewhere = results;
  std::shuffle(elsewhere.begin(), elsewhere.end(), std::mt19937(7));
  for (proto::SweepCaseResult& result : elsewhere) {
    result.set_wall_s(123.25);
    result.set_real_time_factor(0.5);
  }
  const auto json = SummaryJson(SummariseSweep(sweep, results));
  const auto json_elsewhere = SummaryJson(SummariseSweep(sweep, elsewhere));
  ASSERT_TRUE(json.ok());
  ASSERT_TRUE(json_elsewhere.ok());
  EXPECT_EQ(json.value(), json_elsewhere.value());
  EXPECT_THAT(json.value(), HasSubstr("\"pass_rate_lower\": "));
  EXPECT_THAT(json.value(), HasSubstr("\"kind\": \"MARGIN_QUANTILE\""));
  EXPECT_THAT(json.value(), HasSubstr("\"not_run\": \"1\""));
  EXPECT_THAT(json.value(), Not(HasSubstr("wall")));
  EXPECT_THAT(json.value(), Not(HasSubstr("real_time")));
}

TEST(SummaryJsonTest, ShowsNoMeasurementWhereNothingWasMeasured) {
  LoadedSweep sweep = TwoScenarios();
  proto::Criterion criterion = PassRate("not_dropped", 0.5);
  criterion.set_scenario("b");
  *sweep.spec.add_criterion() = criterion;
  const auto json = SummaryJson(SummariseSweep(sweep, {}));
  ASSERT_TRUE(json.ok());
  EXPECT_THAT(json.value(), Not(HasSubstr("\"measured\"")));
  EXPECT_THAT(json.value(), Not(HasSubstr("\"margin\"")));
  EXPECT_THAT(json.value(), HasSubstr("\"passed\": false"));
}

}  // namespace
}  // namespace hilrig::host
