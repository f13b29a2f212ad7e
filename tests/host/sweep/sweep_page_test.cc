#include "host/sweep/sweep_page.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "host/sweep/sweep_statistics.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A sweep of one scenario with a grasp force band over one axis, and a pass-rate criterion.
LoadedSweep GraspSweep(const std::string& sweep_name = "grasp <sweep>") {
  LoadedSweep sweep;
  sweep.file = "sweep.textproto";
  sweep.spec.set_name(sweep_name);
  sweep.spec.add_axis()->set_path("object.mass_kg");
  proto::Criterion* criterion = sweep.spec.add_criterion();
  criterion->set_envelope("grasp_force");
  criterion->set_min_pass_rate(0.5);
  SweepScenario scenario;
  scenario.path = "scenes/grasp & hold.textproto";
  scenario.spec.set_name("grasp");
  proto::Envelope* band = scenario.spec.add_envelopes();
  band->set_name("grasp_force");
  band->set_signal(proto::GRASP_FORCE_N);
  band->set_lower(0.25);
  band->set_upper(0.65);
  sweep.scenarios.push_back(std::move(scenario));
  return sweep;
}

proto::SweepCaseResult Row(std::uint64_t index, proto::SweepCaseResult::Outcome outcome,
                           double worst, bool met) {
  proto::SweepCaseResult row;
  row.set_index(index);
  row.set_scenario("grasp");
  row.set_seed(index + 1);
  row.add_value(0.25);
  row.set_outcome(outcome);
  row.set_real_time_factor(1000 + static_cast<double>(index));
  row.set_wall_s(0.01);
  if (CaseRan(outcome)) {
    auto* envelope = row.add_envelope();
    envelope->set_name("grasp_force");
    envelope->set_met(met);
    envelope->set_worst(worst);
    envelope->set_margin(met ? 0.05 : -0.05);
  }
  return row;
}

proto::SweepSummary Summary(const LoadedSweep& sweep,
                            const std::vector<proto::SweepCaseResult>& results,
                            std::uint64_t sweep_cases) {
  proto::SweepSummary summary = SummariseSweep(sweep, results);
  summary.set_sweep_cases(sweep_cases);
  return summary;
}

std::string Page(const LoadedSweep& sweep, const std::vector<proto::SweepCaseResult>& results,
                 std::uint64_t sweep_cases) {
  return SweepPageHtml(sweep, results, Summary(sweep, results, sweep_cases), "/opt/hilrig",
                       "/out/runs");
}

TEST(SweepPageTest, ShowsTheVerdictTheCriteriaThePassRatesAndAHistogramWithTheLimits) {
  const LoadedSweep sweep = GraspSweep();
  const std::vector<proto::SweepCaseResult> results = {
      Row(0, proto::SweepCaseResult::PASSED, 0.6, true),
      Row(1, proto::SweepCaseResult::PASSED, 0.55, true),
      Row(2, proto::SweepCaseResult::FAILED, 0.7, false)};
  const std::string html = Page(sweep, results, 3);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_THAT(html, HasSubstr("<h2>Criteria</h2>"));
  EXPECT_THAT(html, HasSubstr("<h2>Envelopes</h2>"));
  // 2 of 3 met: the Wilson lower bound at 95 % (0.2077) is under 0.5, so the criterion fails.
  EXPECT_THAT(html, HasSubstr("<span class=\"badge fail\">FAIL</span>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"fail\">FAIL</td><td class=\"num\">0</td><td>grasp</td>"
                              "<td>grasp_force</td><td>pass rate (Wilson lower bound)</td>"
                              "<td class=\"num\">0.2077</td><td class=\"num\">0.5</td>"));
  EXPECT_THAT(html, HasSubstr("<td>grasp</td><td>grasp_force</td><td>N</td>"
                              "<td class=\"num\">2 / 3</td><td class=\"fail num\">66.67 %</td>"
                              "<td class=\"num\">[20.77 %, 93.85 %]</td>"));
  EXPECT_THAT(html, HasSubstr("3 of 3 cases finished: 1 failed, 2 passed"));
  // The histogram, inlined, with both limits and the cases counted met and not met.
  EXPECT_THAT(html, HasSubstr("<svg xmlns=\"http://www.w3.org/2000/svg\""));
  EXPECT_THAT(html, Not(HasSubstr("<?xml")));
  EXPECT_THAT(html, HasSubstr(">lower 0.25 N</text>"));
  EXPECT_THAT(html, HasSubstr(">upper 0.65 N</text>"));
  EXPECT_THAT(html, HasSubstr(">met (2)</text>"));
  EXPECT_THAT(html, HasSubstr(">not met (1)</text>"));
  EXPECT_THAT(html, HasSubstr("<a href=\"failing.txt\">failing.txt</a>"));
  EXPECT_THAT(html, Not(HasSubstr("<script")));
}

TEST(SweepPageTest, AnAblationsEnvelopeSaysItIsExpectedToFail) {
  LoadedSweep sweep = GraspSweep();
  sweep.scenarios[0].spec.mutable_envelopes(0)->set_expect(proto::FAIL);
  const std::string html =
      Page(sweep, {Row(0, proto::SweepCaseResult::PASSED, 0.7, true)}, /*sweep_cases=*/1);
  EXPECT_THAT(html, HasSubstr("<td>grasp</td><td>grasp_force (expect FAIL)</td><td>N</td>"));
  EXPECT_THAT(Page(GraspSweep(), {Row(0, proto::SweepCaseResult::PASSED, 0.6, true)}, 1),
              Not(HasSubstr("expect FAIL")));
}

TEST(SweepPageTest, AFailingCaseHasItsCommandEscapedAndALinkToItsRunFolder) {
  const LoadedSweep sweep = GraspSweep();
  const std::vector<proto::SweepCaseResult> results = {
      Row(3, proto::SweepCaseResult::FAILED, 0.7, false),
      Row(4, proto::SweepCaseResult::INVALID, 0, false)};
  const std::string html = Page(sweep, results, 2);
  EXPECT_THAT(html, HasSubstr("<h1>Sweep grasp &lt;sweep&gt; "));
  EXPECT_THAT(html, Not(HasSubstr("<sweep>")));
  EXPECT_THAT(html, HasSubstr("<code>/opt/hilrig run &apos;scenes/grasp &amp; hold.textproto&apos;"
                              " --seed 4 --set object.mass_kg=0.25 --no-reference --out "
                              "/out/runs/case-0000003</code>"));
  EXPECT_THAT(html, HasSubstr("<a href=\"runs/case-0000003/index.html\">3</a>"));
  EXPECT_THAT(html, Not(HasSubstr("runs/case-0000004/index.html")));  // it never ran
  EXPECT_THAT(html, HasSubstr("<td class=\"fail\">invalid</td>"));
}

TEST(SweepPageTest, ListsAtMostAHundredFailingCasesAndSaysHowManyMore) {
  const LoadedSweep sweep = GraspSweep();
  std::vector<proto::SweepCaseResult> results;
  for (std::uint64_t i = 0; i < 150; ++i) {
    results.push_back(Row(i, proto::SweepCaseResult::FAILED, 0.7, false));
  }
  const std::string html = Page(sweep, results, 150);
  EXPECT_THAT(html, HasSubstr("/out/runs/case-0000099</code>"));
  EXPECT_THAT(html, Not(HasSubstr("/out/runs/case-0000100</code>")));
  EXPECT_THAT(html, HasSubstr("50 more in <a href=\"failing.txt\">failing.txt</a>"));
}

TEST(SweepPageTest, WorstValuesThatAreNotFiniteAreCountedNotDrawn) {
  const LoadedSweep sweep = GraspSweep();
  const std::vector<proto::SweepCaseResult> results = {
      Row(0, proto::SweepCaseResult::FAILED, kNaN, false),
      Row(1, proto::SweepCaseResult::FAILED, kInf, false),
      Row(2, proto::SweepCaseResult::PASSED, 0.5, true)};
  const std::string html = Page(sweep, results, 3);
  EXPECT_THAT(html, HasSubstr(">2 not finite, not drawn</text>"));
  const std::vector<proto::SweepCaseResult> all_nan = {
      Row(0, proto::SweepCaseResult::FAILED, kNaN, false)};
  EXPECT_THAT(Page(sweep, all_nan, 1), HasSubstr(">no finite value to draw</text>"));
}

TEST(SweepPageTest, ASweepWithoutFinishedCasesIsIncompleteAndDrawsNothing) {
  const LoadedSweep sweep = GraspSweep();
  const std::string html = Page(sweep, {}, 10);
  EXPECT_THAT(html, HasSubstr("<span class=\"badge neutral\">INCOMPLETE</span>"));
  EXPECT_THAT(html, HasSubstr("0 of 10 cases finished"));
  EXPECT_THAT(html, HasSubstr("No case has finished: nothing to draw."));
  EXPECT_THAT(html, Not(HasSubstr("<svg")));
  EXPECT_THAT(html, HasSubstr("<h2>Cases that did not pass</h2>\n<p>None.</p>"));
}

TEST(SweepPageTest, ASweepWithoutCriteriaSaysItCannotPass) {
  LoadedSweep sweep = GraspSweep();
  sweep.spec.clear_criterion();
  const std::string html = Page(sweep, {Row(0, proto::SweepCaseResult::PASSED, 0.5, true)}, 1);
  EXPECT_THAT(html, HasSubstr("The sweep sets no criterion"));
  EXPECT_THAT(html, HasSubstr("<span class=\"badge fail\">FAIL</span>"));
}

// Over two axes the page draws the pass map and links map.svg, the same map as a file; over one
// axis it has neither.
TEST(SweepPageTest, ASweepOverTwoAxesShowsItsPassMapAndLinksTheFile) {
  LoadedSweep sweep = GraspSweep();
  for (const double mass_kg : {0.25, 0.5})
    sweep.spec.mutable_axis(0)->mutable_list()->add_value(mass_kg);
  proto::Axis* force = sweep.spec.add_axis();
  force->set_path("timeline[0].grasp.force_n");
  for (const double force_n : {2.0, 3.0}) force->mutable_list()->add_value(force_n);
  // Cases 0..3: (0.25, 2), (0.25, 3), (0.5, 2), (0.5, 3); the last fails.
  std::vector<proto::SweepCaseResult> results;
  for (std::uint64_t index = 0; index < 4; ++index) {
    results.push_back(index == 3 ? Row(index, proto::SweepCaseResult::FAILED, 0.7, false)
                                 : Row(index, proto::SweepCaseResult::PASSED, 0.5, true));
  }
  const std::string html = Page(sweep, results, 4);
  EXPECT_THAT(html, HasSubstr("<h2>Pass map</h2>"));
  EXPECT_THAT(html, HasSubstr("A cell per point of object.mass_kg (across) and "
                              "timeline[0].grasp.force_n (up)"));
  EXPECT_THAT(html, HasSubstr("<title>object.mass_kg = 0.5, timeline[0].grasp.force_n = 3: 0 of 1 "
                              "case passed</title>"));
  EXPECT_THAT(html, HasSubstr(">fail</text>"));
  EXPECT_THAT(html, HasSubstr("fill=\"#D55E00\""));
  EXPECT_THAT(html, HasSubstr("a file of its own, <a href=\"map.svg\">map.svg</a>."));
  EXPECT_THAT(html, HasSubstr("<a href=\"map.svg\">map.svg</a> </p>"));  // in the files
  EXPECT_THAT(html, Not(HasSubstr("more axes than a map shows")));
  // A third axis: the map keeps the first two and says which axes its points gather.
  proto::Axis* latency = sweep.spec.add_axis();
  latency->set_path("models.vio.latency_s");
  latency->mutable_list()->add_value(0.01);
  EXPECT_THAT(Page(sweep, results, 4),
              HasSubstr("a point holds the cases of every value of the others "
                        "(models.vio.latency_s)."));

  const std::string one_axis = Page(GraspSweep(), results, 4);
  EXPECT_THAT(one_axis, Not(HasSubstr("Pass map")));
  EXPECT_THAT(one_axis, Not(HasSubstr("map.svg")));
}

// The page is made from what the cases showed, never from how fast they ran: the timing columns
// differ between machines and between a local sweep and a cluster's.
TEST(SweepPageTest, ThePageDoesNotDependOnTheCasesTiming) {
  const LoadedSweep sweep = GraspSweep();
  std::vector<proto::SweepCaseResult> results = {
      Row(0, proto::SweepCaseResult::PASSED, 0.6, true),
      Row(1, proto::SweepCaseResult::FAILED, 0.7, false)};
  const std::string html = Page(sweep, results, 2);
  for (proto::SweepCaseResult& row : results) {
    row.set_real_time_factor(row.real_time_factor() * 3);
    row.set_wall_s(row.wall_s() * 7);
  }
  EXPECT_EQ(Page(sweep, results, 2), html);
}

}  // namespace
}  // namespace hilrig::host
