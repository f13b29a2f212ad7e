// A result folder told by its files, and a report that cannot be read named with its file.
#include "host/compare/result_folder.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

TEST(ResultFolderTest, TellsARunFromASweepAndRefusesNeither) {
  const fs::path dir = FreshTestDir("result_folder");
  fs::create_directories(dir / "run");
  std::ofstream(dir / "run" / "report.json") << "{\"scenario\": \"hover\", \"passed\": true}";
  fs::create_directories(dir / "sweep" / "runs" / "case-0000001");
  std::ofstream(dir / "sweep" / "summary.json") << "{\"sweep\": \"s\", \"cases\": \"3\"}";
  std::ofstream(dir / "sweep" / "runs" / "case-0000001" / "report.json") << "{}";
  fs::create_directories(dir / "empty");
  // A folder run: a run folder per scenario, beside the summary page.
  for (const char* scene : {"load_ramp", "hover"}) {
    fs::create_directories(dir / "suite" / scene);
    std::ofstream(dir / "suite" / scene / "report.json") << "{}";
  }
  fs::create_directories(dir / "suite" / "did_not_run");
  std::ofstream(dir / "suite" / "index.html") << "<!DOCTYPE html>";
  EXPECT_EQ(ResultFolderKindOf((dir / "suite").string()).value(), ResultFolderKind::kSuite);
  EXPECT_EQ(SuiteRunNames((dir / "suite").string()).value(),
            (std::vector<std::string>{"hover", "load_ramp"}));
  EXPECT_EQ(ResultFolderKindOf((dir / "run").string()).value(), ResultFolderKind::kRun);
  EXPECT_EQ(ResultFolderKindOf((dir / "sweep").string()).value(), ResultFolderKind::kSweep);
  const auto empty = ResultFolderKindOf((dir / "empty").string());
  ASSERT_FALSE(empty.ok());
  EXPECT_THAT(empty.error().message, HasSubstr("holds neither a run's report.json"));
  EXPECT_FALSE(ResultFolderKindOf((dir / "missing").string()).ok());
  EXPECT_EQ(ReadRunReport((dir / "run").string()).value().scenario(), "hover");
  EXPECT_EQ(ReadSweepSummary((dir / "sweep").string()).value().cases(), 3u);
}

TEST(ResultFolderTest, AReportThatIsNotJsonIsNamed) {
  const fs::path dir = FreshTestDir("result_folder");
  std::ofstream(dir / "report.json") << "{\"scenario\": ";
  const auto report = ReadRunReport(dir.string());
  ASSERT_FALSE(report.ok());
  EXPECT_THAT(report.error().message, HasSubstr("report.json is not a Report in JSON"));
  // A later build's field is skipped, not refused.
  std::ofstream(dir / "report.json", std::ios::trunc) << "{\"scenario\": \"x\", \"new_field\": 1}";
  EXPECT_EQ(ReadRunReport(dir.string()).value().scenario(), "x");
}

}  // namespace
}  // namespace hilrig::host
