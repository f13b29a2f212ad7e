#include "host/report/run_folder.h"

#include <gmock/gmock.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "host/report/report_files.h"
#include "host/report/stop_reason.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

proto::Report ReadReport(const fs::path& path) {
  proto::Report report;
  const auto status = google::protobuf::util::JsonStringToMessage(ReadFile(path), &report);
  EXPECT_TRUE(status.ok()) << path << ": " << status.ToString();
  return report;
}

// What a finished, passing run leaves in its folder.
void LeaveAPassingRun(const fs::path& dir) {
  proto::Report passed;
  passed.set_scenario("hover");
  SetStop({StopReason::kCompleted, {}}, passed);
  passed.set_passed(true);
  passed.set_simulated_s(40);
  ASSERT_TRUE(WriteReportFiles(passed, dir.string()));
  for (const char* plot : {"force.svg", "load.svg", "position.svg"}) {
    ASSERT_TRUE(WriteTextFile((dir / plot).string(), "<svg/>"));
  }
}

TEST(RunOutputFolderTest, ClaimingAUsedFolderMarksItIncompleteBeforeTheRunWritesAnything) {
  const fs::path dir = FreshTestDir("run_folder_");
  LeaveAPassingRun(dir);

  auto folder = RunOutputFolder::Claim(dir.string(), "hover", "hover.textproto");
  ASSERT_TRUE(folder) << folder.error().message;

  const proto::Report report = ReadReport(dir / "report.json");
  EXPECT_EQ(report.stop_reason(), "incomplete");
  EXPECT_EQ(report.stop_kind(), proto::STOP_INCOMPLETE);
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(report.scenario(), "hover");
  EXPECT_EQ(report.spec_file(), "hover.textproto");
  EXPECT_EQ(report.simulated_s(), 0);
  const std::string junit = ReadFile(dir / "junit.xml");
  EXPECT_THAT(junit, HasSubstr("failures=\"1\""));
  EXPECT_THAT(junit, HasSubstr("<failure message=\"incomplete at 0 s simulated\"/>"));
  const std::string page = ReadFile(dir / "index.html");
  EXPECT_THAT(page, HasSubstr("<span class=\"badge neutral\">INCOMPLETE</span>"));
  EXPECT_THAT(page, Not(HasSubstr("PASS"))) << "the previous run's page";
  for (const char* plot : {"force.svg", "load.svg", "position.svg"}) {
    EXPECT_FALSE(fs::exists(dir / plot)) << plot << " of the previous run";
  }
}

TEST(RunOutputFolderTest, TheIncompleteReportSaysHowFarTheRunGot) {
  const fs::path dir = FreshTestDir("run_folder_");
  auto folder = RunOutputFolder::Claim(dir.string(), "hover", "hover.textproto");
  ASSERT_TRUE(folder) << folder.error().message;
  std::ostringstream notes;

  folder.value().Reached(12.5, notes);

  EXPECT_EQ(ReadReport(dir / "report.json").simulated_s(), 12.5);
  EXPECT_EQ(ReadReport(dir / "report.json").stop_reason(), "incomplete");
  EXPECT_THAT(ReadFile(dir / "junit.xml"), HasSubstr("incomplete at 12.5 s simulated"));
  EXPECT_THAT(ReadFile(dir / "index.html"), HasSubstr("incomplete at 12.5 s simulated"));
  EXPECT_EQ(notes.str(), "");
}

TEST(RunOutputFolderTest, TheFinalReportReplacesTheIncompleteOne) {
  const fs::path dir = FreshTestDir("run_folder_");
  auto folder = RunOutputFolder::Claim(dir.string(), "hover", "hover.textproto");
  ASSERT_TRUE(folder) << folder.error().message;
  proto::Report final_report;
  SetStop({StopReason::kCompleted, {}}, final_report);
  final_report.set_passed(true);

  ASSERT_TRUE(folder.value().Finish(final_report));

  EXPECT_TRUE(ReadReport(dir / "report.json").passed());
  EXPECT_THAT(ReadFile(dir / "junit.xml"), HasSubstr("failures=\"0\""));
  EXPECT_THAT(ReadFile(dir / "index.html"), HasSubstr("<span class=\"badge pass\">PASS</span>"));
}

TEST(RunOutputFolderTest, AFolderAnotherRunHoldsIsRefusedAndLeftAlone) {
  const fs::path dir = FreshTestDir("run_folder_");
  auto first = RunOutputFolder::Claim(dir.string(), "hover", "hover.textproto");
  ASSERT_TRUE(first) << first.error().message;
  first.value().Reached(3, std::cerr);

  auto second = RunOutputFolder::Claim(dir.string(), "other", "other.textproto");
  ASSERT_FALSE(second);
  EXPECT_THAT(second.error().message, HasSubstr("is in use"));
  EXPECT_EQ(ReadReport(dir / "report.json").scenario(), "hover");
  EXPECT_EQ(ReadReport(dir / "report.json").simulated_s(), 3);
}

}  // namespace
}  // namespace hilrig::host
