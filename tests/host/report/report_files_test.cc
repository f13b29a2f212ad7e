#include "host/report/report_files.h"

#include <gmock/gmock.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/report/stop_reason.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

proto::Report TwoEnvelopeReport() {
  proto::Report report;
  report.set_scenario("hover <&>");
  SetStop({StopReason::kCompleted, {}}, report);
  report.set_real_time_factor(1234.5);
  proto::EnvelopeResult* good = report.add_envelopes();
  good->set_name("altitude");
  good->set_verdict(proto::PASS);
  good->set_meets_expectation(true);
  good->set_worst_value(0.01);
  good->set_worst_at_s(3);
  good->set_upper(0.05);
  good->set_samples_checked(10);
  proto::EnvelopeResult* bad = report.add_envelopes();
  bad->set_name("tilt \"max\"");
  bad->set_verdict(proto::FAIL);
  bad->set_meets_expectation(false);
  bad->set_worst_value(20);
  bad->set_worst_at_s(7);
  bad->set_first_violation_at_s(6.5);
  bad->set_upper(15);
  bad->set_samples_checked(10);
  return report;
}

std::string ReadFile(const fs::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

fs::path TempFile(const std::string& name) { return fs::path(::testing::TempDir()) / name; }

TEST(ReportFilesTest, JsonRoundTripsToTheSameReport) {
  const proto::Report report = TwoEnvelopeReport();
  ASSERT_TRUE(WriteJsonFile(report, TempFile("report.json").string()).ok());
  proto::Report parsed;
  ASSERT_TRUE(
      google::protobuf::util::JsonStringToMessage(ReadFile(TempFile("report.json")), &parsed).ok());
  EXPECT_EQ(parsed.SerializeAsString(), report.SerializeAsString());
}

TEST(ReportFilesTest, JunitHasOneEscapedCasePerEnvelopeAndFailsTheUnmetOne) {
  ASSERT_TRUE(WriteJunitXml(TwoEnvelopeReport(), TempFile("junit.xml").string()).ok());
  const std::string xml = ReadFile(TempFile("junit.xml"));
  EXPECT_THAT(xml, HasSubstr("testsuite name=\"hover &lt;&amp;&gt;\" tests=\"2\" failures=\"1\""));
  EXPECT_THAT(xml, HasSubstr("name=\"tilt &quot;max&quot;\""));
  EXPECT_EQ(xml.find("<failure"), xml.rfind("<failure"));  // exactly one failure
}

TEST(ReportFilesTest, IncompleteRunIsAFailedCase) {
  proto::Report report = TwoEnvelopeReport();
  SetStop({StopReason::kInterrupted, {}}, report);
  ASSERT_TRUE(WriteJunitXml(report, TempFile("junit2.xml").string()).ok());
  EXPECT_THAT(ReadFile(TempFile("junit2.xml")), HasSubstr("tests=\"3\" failures=\"2\""));
}

TEST(ReportFilesTest, TargetChecksAreCasesAndTheTargetHasALine) {
  proto::Report report = TwoEnvelopeReport();
  proto::TimingCheckResult* check = report.add_target_checks();
  check->set_name("work_p99_fraction_max");
  check->set_evaluated(true);
  check->set_passed(false);
  check->set_value(0.6);
  check->set_limit(0.5);
  check->set_unit("fraction");
  ASSERT_TRUE(WriteJunitXml(report, TempFile("junit3.xml").string()).ok());
  const std::string xml = ReadFile(TempFile("junit3.xml"));
  EXPECT_THAT(xml, HasSubstr("tests=\"3\" failures=\"2\""));
  EXPECT_THAT(xml, HasSubstr("name=\"target work_p99_fraction_max\""));
  EXPECT_THAT(xml, HasSubstr("FAIL  target work_p99_fraction_max  60 %  limit 50 %"));

  proto::Target target;
  target.set_board("stm32f405");
  target.set_core_clock_hz(168'000'000);
  target.set_control_period_s(0.001);
  target.set_steps_measured(3000);
  target.set_work_p50_cycles(1302);
  target.set_work_p99_cycles(1410);
  target.set_work_max_cycles(2210);
  target.set_work_p50_fraction(1302 / 168e3);
  target.set_work_p99_fraction(1410 / 168e3);
  target.set_work_max_fraction(2210 / 168e3);
  target.set_flash_used_bytes(41234);
  target.set_ram_used_bytes(6120);
  EXPECT_EQ(FormatTargetLine(target),
            "target stm32f405 at 168 MHz: work per control step p50 1302, p99 1410, max 2210 "
            "cycles (0.775 %, 0.839 %, 1.32 % of 1000 us) over 3000 steps; flash 41234 B, RAM "
            "6120 B");
  // On QEMU the counts are virtual time, 5.95 instructions each at 168 MHz: the line says so and
  // what the p99 means for a real core (1410 x 5.95 = 8393 instructions, 5 % of 1 ms).
  target.set_emulated_core(true);
  EXPECT_EQ(FormatTargetLine(target),
            "target stm32f405 at 168 MHz: work per control step p50 1302, p99 1410, max 2210 "
            "SysTick counts of QEMU's virtual time (not cycles: 5.95 instructions each, so p99 is "
            "8393 instructions; a real 168 MHz core needs at least as many cycles, 5 % of 1000 us "
            "or more) over 3000 steps; flash 41234 B, RAM 6120 B");
  // A target that measures nothing and knows neither its clock nor its memory says so.
  proto::Target host;
  host.set_board("host");
  EXPECT_EQ(FormatTargetLine(host), "target host: work per control step not measured");
}

TEST(ReportFilesTest, WritingIntoAMissingFolderIsAnError) {
  EXPECT_FALSE(WriteJsonFile(TwoEnvelopeReport(), "/nonexistent/dir/report.json").ok());
}

TEST(ReportFilesTest, EnvelopeLineShowsVerdictWorstValueTimeAndLimit) {
  const proto::Report report = TwoEnvelopeReport();
  EXPECT_EQ(FormatEnvelopeLine(report.envelopes(0)),
            "PASS  altitude  worst 0.01 at 3 s  limit [-, 0.05]");
  EXPECT_THAT(FormatEnvelopeLine(report.envelopes(1)), HasSubstr("first out at 6.5 s"));
}

TEST(ReportFilesTest, TimingLineCarriesTheRealTimeFactor) {
  EXPECT_THAT(FormatTimingLine(TwoEnvelopeReport()), HasSubstr("real-time factor 1234x"));
}

TEST(ReportFilesTest, TimingLineGivesASlowRunsFactorInTwoDigits) {
  proto::Report report = TwoEnvelopeReport();
  report.set_real_time_factor(0.2712);
  EXPECT_THAT(FormatTimingLine(report), HasSubstr("real-time factor 0.27x"));
  report.set_real_time_factor(3.46);
  EXPECT_THAT(FormatTimingLine(report), HasSubstr("real-time factor 3.5x"));
}

TEST(ReportFilesTest, FidelityErrorLineNamesTheReferenceAndGivesGraspFiguresOnlyInGraspScenes) {
  proto::FidelityError error;
  error.set_reference_fidelity("DP(1e-10) x8 tiles:64");
  error.set_reference_cached(true);
  error.set_grasp_force_rms_n(0.0012);
  error.set_position_rms_m(2.5e-5);
  error.set_position_max_m(1e-4);

  const std::string grasp = FormatFidelityErrorLine(error, true);
  const std::string hover = FormatFidelityErrorLine(error, false);

  EXPECT_EQ(grasp,
            "fidelity error vs reference DP(1e-10) x8 tiles:64 (cached): grasp force RMS 0.0012 N "
            "(max 0), load RMS 0 N (max 0), position RMS 2.5e-05 m (max 0.0001)");
  EXPECT_EQ(hover,
            "fidelity error vs reference DP(1e-10) x8 tiles:64 (cached): position RMS 2.5e-05 m "
            "(max 0.0001)");
}

}  // namespace
}  // namespace hilrig::host
