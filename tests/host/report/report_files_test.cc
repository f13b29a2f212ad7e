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
