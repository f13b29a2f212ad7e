#include "host/report/run_page.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>

#include "host/report/report_files.h"
#include "host/report/stop_reason.h"
#include "host/report/svg_plot.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

proto::Report GraspReport() {
  proto::Report report;
  report.set_scenario("balloon <grasp> & \"hold\"");
  report.set_spec_file("scenarios/balloon_grasp.textproto");
  report.set_seed(7);
  SetStop({StopReason::kCompleted, {}}, report);
  report.set_passed(false);
  report.set_simulated_s(34);
  report.set_real_time_factor(586.2);
  report.set_can_frames_logged(12138);
  proto::EnvelopeResult* force = report.add_envelopes();
  force->set_name("grasp_force");
  force->set_signal(proto::GRASP_FORCE_N);
  force->set_verdict(proto::PASS);
  force->set_meets_expectation(true);
  force->set_worst_value(0.6015);
  force->set_worst_at_s(28.73);
  force->set_lower(0.25);
  force->set_upper(0.65);
  force->set_margin(0.0485);
  force->set_samples_checked(2801);
  proto::EnvelopeResult* tilt = report.add_envelopes();
  tilt->set_name("tilt");
  tilt->set_signal(proto::TILT_DEG);
  tilt->set_verdict(proto::FAIL);
  tilt->set_meets_expectation(false);
  tilt->set_worst_value(std::numeric_limits<double>::quiet_NaN());
  tilt->set_worst_at_s(3);
  tilt->set_first_violation_at_s(2.5);
  tilt->set_upper(15);
  tilt->set_margin(-std::numeric_limits<double>::infinity());
  tilt->set_samples_checked(10);
  proto::EnvelopeResult* ablation = report.add_envelopes();
  ablation->set_name("slips_without_feedback");
  ablation->set_signal(proto::OBJECT_DROPPED);
  ablation->set_verdict(proto::FAIL);
  ablation->set_expected(proto::FAIL);
  ablation->set_meets_expectation(true);
  ablation->set_worst_value(1);
  ablation->set_upper(0);
  ablation->set_samples_checked(10);
  proto::ObjectOutcome* balloon = report.add_objects();
  balloon->set_fixture("balloon");
  balloon->set_damage("burst");
  balloon->set_damaged_at_s(12.5);
  balloon->set_final_state("released");
  balloon->set_peak_normal_force_n(0.46);
  proto::Metric* imu = report.add_metrics();
  imu->set_name("dut_imu_messages");
  imu->set_value(34000);
  imu->set_unit("count");
  proto::Metric* tilt_rms = report.add_metrics();
  tilt_rms->set_name("tilt_rms");
  tilt_rms->set_value(0.27);
  tilt_rms->set_unit("deg");
  return report;
}

std::string PositionSvg() {
  TimePlot plot;
  plot.title = "Position error";
  plot.y_label = "error (m)";
  plot.series = {{"altitude error", {0, 1, 2}, {0.01, 0.02, 0.015}, "", false}};
  return RenderSvg(plot);
}

TEST(RunPageTest, ShowsTheVerdictTheEnvelopesWithLimitsAndTheObjects) {
  const std::string html = RunPageHtml(GraspReport(), {});
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_THAT(html, HasSubstr("<span class=\"badge fail\">FAIL</span>"));
  EXPECT_THAT(html, HasSubstr("<h2>Envelopes</h2>"));
  // grasp_force: its verdict, worst value with unit, when, limits and margin in one row.
  EXPECT_THAT(html, HasSubstr("<td class=\"pass\">PASS</td><td>grasp_force</td><td>GRASP_FORCE_N"
                              "</td><td class=\"num\">0.6015 N</td><td class=\"num\">28.73 s</td>"
                              "<td class=\"num\">[0.25, 0.65] N</td><td class=\"num\">0.0485 N</td>"
                              "<td>-</td><td>PASS</td></tr>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"fail\">PASS, NOT MET</td>"));
  // An ablation's envelope fails as its spec expects: red verdict, green expectation.
  EXPECT_THAT(html, HasSubstr("<td class=\"fail\">FAIL</td><td>slips_without_feedback</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"pass\">FAIL, met</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">[-, 15] deg</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">2.5 s</td>"));  // first out at
  EXPECT_THAT(html, HasSubstr("<td>balloon</td><td class=\"fail\">burst</td>"
                              "<td class=\"num\">12.5 s</td><td>released</td>"));
  EXPECT_THAT(html, HasSubstr("<td>real-time factor</td><td class=\"num\">586x</td>"));
  EXPECT_THAT(html, HasSubstr("<td>CAN frames logged</td><td class=\"num\">12138</td>"));
  EXPECT_THAT(html, HasSubstr("<td>dut_imu_messages</td><td class=\"num\">34000</td>"));
  EXPECT_THAT(html, HasSubstr("<td>tilt_rms</td><td class=\"num\">0.27 deg</td>"));
  EXPECT_THAT(html, HasSubstr("<a href=\"trace.csv\">trace.csv</a>"));
}

TEST(RunPageTest, EscapesTheSpecsTextAndShowsNonFiniteNumbersAsWords) {
  const std::string html = RunPageHtml(GraspReport(), {});
  EXPECT_THAT(html, HasSubstr("<title>balloon &lt;grasp&gt; &amp; &quot;hold&quot;: FAIL</title>"));
  EXPECT_THAT(html, HasSubstr("<h1>balloon &lt;grasp&gt; &amp; &quot;hold&quot; "));
  EXPECT_THAT(html, Not(HasSubstr("<grasp>")));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">nan deg</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">-inf deg</td>"));
}

TEST(RunPageTest, InlinesThePlotsWithIdsOfTheirOwnAndNamesAMissingOne) {
  const std::string svg = PositionSvg();
  ASSERT_THAT(svg, HasSubstr("id=\"plot-area\""));
  const std::string html =
      RunPageHtml(GraspReport(), {{"force.svg", ""}, {"position.svg", svg}, {"load.svg", svg}});
  EXPECT_THAT(html, Not(HasSubstr("<?xml")));
  EXPECT_THAT(html, HasSubstr("force.svg could not be read."));
  EXPECT_THAT(html, HasSubstr("<svg xmlns=\"http://www.w3.org/2000/svg\""));
  EXPECT_THAT(html, HasSubstr("id=\"plot0-plot-area\""));
  EXPECT_THAT(html, HasSubstr("url(#plot0-plot-area)"));
  EXPECT_THAT(html, HasSubstr("id=\"plot1-plot-area\""));
  EXPECT_THAT(html, Not(HasSubstr("\"plot-area\"")));
  EXPECT_THAT(html, Not(HasSubstr("url(#plot-area)")));
}

TEST(RunPageTest, LoadsNothingAndRunsNoScript) {
  const std::string html = RunPageHtml(GraspReport(), {{"position.svg", PositionSvg()}});
  EXPECT_THAT(html, HasSubstr("<meta http-equiv=\"Content-Security-Policy\" "
                              "content=\"default-src 'none'; style-src 'unsafe-inline'\">"));
  EXPECT_THAT(html, Not(HasSubstr("<script")));
  EXPECT_THAT(html, Not(HasSubstr("src=")));
  EXPECT_THAT(html, Not(HasSubstr("<link")));
}

TEST(RunPageTest, AnIncompleteRunReadsIncompleteAndAnEnvelopeWithoutSamplesSaysSo) {
  proto::Report report;
  report.set_scenario("hover");
  SetStop({StopReason::kIncomplete, {}}, report);
  report.set_simulated_s(12.5);
  proto::EnvelopeResult* late = report.add_envelopes();
  late->set_name("late");
  late->set_upper(1);
  late->set_meets_expectation(true);
  const std::string html = RunPageHtml(report, {});
  EXPECT_THAT(html, HasSubstr("<span class=\"badge neutral\">INCOMPLETE</span>"));
  EXPECT_THAT(html, HasSubstr("incomplete at 12.5 s simulated"));
  EXPECT_THAT(html, HasSubstr("<td>no samples in its window</td>"));
  EXPECT_THAT(html, Not(HasSubstr("badge pass")));
}

TEST(RunPageTest, WriteRunPageInlinesThePlotFilesTheReportLists) {
  const fs::path dir = FreshTestDir("run_page_");
  ASSERT_TRUE(WriteTextFile((dir / "position.svg").string(), PositionSvg()));
  proto::Report report = GraspReport();
  report.add_plots("position.svg");
  report.add_plots("force.svg");  // listed, not there
  ASSERT_TRUE(WriteRunPage(report, dir.string()));
  const std::string html = ReadFile(dir / kRunPageFile);
  EXPECT_THAT(html, HasSubstr("id=\"plot0-plot-area\""));
  EXPECT_THAT(html, HasSubstr("force.svg could not be read."));
}

}  // namespace
}  // namespace hilrig::host
