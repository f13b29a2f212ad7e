// A sweep's runs.csv read back for a comparison: the cases' numbers, seeds, axis values and
// outcomes out of the merge's columns, quoted fields that hold commas, quotes and line breaks,
// and every way a damaged file is refused, named with its file and the line.
#include "host/compare/runs_csv.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

constexpr const char* kHeader =
    "case,scenario,seed,vehicle.mass_kg,envelopes[1].upper,outcome,altitude.met,altitude.worst,"
    "altitude.margin,detail,real_time_factor,wall_s\n";

rig::Result<SweepCaseRows> Parse(const std::string& text) {
  std::istringstream in(text);
  return ParseRunsCsv(in, "base/runs.csv");
}

std::string ErrorOf(const std::string& text) {
  const auto rows = Parse(text);
  return rows.ok() ? "parsed" : rows.error().message;
}

TEST(RunsCsvTest, ReadsEachCasesNumberSeedValuesAndOutcome) {
  const auto rows =
      Parse(std::string(kHeader) +
            "0,hover,1,0.5,1e-09,passed,1,0.01,0.04,,900,0.002\n"
            "1,hover,2,0.5,1e-09,failed,0,0.2,-0.15,\"aborted by altitude, at 0.3 s\",900,0.002\n"
            "\n"  // a blank line is no case
            "2,\"ho,ver\",1,0.30000000000000004,1,stopped,,,,\"dut \"\"x\"\" failed\nat 1 s\",0,0\n"
            "3,hover,2,0.6,1,set_up_failed,,,,,0,0\n");
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  EXPECT_THAT(rows.value().axes, ElementsAre("vehicle.mass_kg", "envelopes[1].upper"));
  ASSERT_EQ(rows.value().cases.size(), 4u);
  const proto::SweepCaseResult& first = rows.value().cases[0];
  EXPECT_EQ(first.index(), 0u);
  EXPECT_EQ(first.scenario(), "hover");
  EXPECT_EQ(first.seed(), 1u);
  EXPECT_THAT(first.value(), ElementsAre(0.5, 1e-9));
  EXPECT_EQ(first.outcome(), proto::SweepCaseResult::PASSED);
  EXPECT_EQ(rows.value().cases[1].outcome(), proto::SweepCaseResult::FAILED);
  const proto::SweepCaseResult& quoted = rows.value().cases[2];
  EXPECT_EQ(quoted.scenario(), "ho,ver");
  EXPECT_THAT(quoted.value(), ElementsAre(0.1 + 0.2, 1.0));  // every digit the writer wrote
  EXPECT_EQ(quoted.outcome(), proto::SweepCaseResult::STOPPED);
  EXPECT_EQ(rows.value().cases[3].outcome(), proto::SweepCaseResult::SET_UP_FAILED);
}

TEST(RunsCsvTest, ASweepWithoutAxesHasNone) {
  const auto rows =
      Parse("case,scenario,seed,outcome,detail,real_time_factor,wall_s\n0,hover,1,passed,,1,1\n");
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  EXPECT_TRUE(rows.value().axes.empty());
  EXPECT_EQ(rows.value().cases.size(), 1u);
}

// Each damage is named with the file and the line of its row; a row after a quoted line break
// is counted from the line it starts on.
TEST(RunsCsvTest, ADamagedFileIsRefusedWithItsFileAndLine) {
  const std::string good = "0,hover,1,0.5,1,passed,1,0,0,,1,1\n";
  const std::string two_line = "1,hover,2,0.5,1,failed,0,0,0,\"a\nb\",1,1\n";
  EXPECT_EQ(ErrorOf(std::string(kHeader) + good + two_line + "2,hover,1,0.5,1,passed,1\n"),
            "base/runs.csv:5: 7 fields where the header has 12");
  EXPECT_EQ(ErrorOf(std::string(kHeader) + good + "1,hover,x,0.5,1,passed,1,0,0,,1,1\n"),
            "base/runs.csv:3: seed \"x\" is not a valid number");
  EXPECT_EQ(ErrorOf(std::string(kHeader) + "-1,hover,1,0.5,1,passed,1,0,0,,1,1\n"),
            "base/runs.csv:2: case \"-1\" is not a valid number");
  EXPECT_EQ(ErrorOf(std::string(kHeader) + "0,hover,1,0.5,heavy,passed,1,0,0,,1,1\n"),
            "base/runs.csv:2: envelopes[1].upper \"heavy\" is not a valid number");
  EXPECT_EQ(ErrorOf(std::string(kHeader) + "0,hover,1,0.5,1,unknown,1,0,0,,1,1\n"),
            "base/runs.csv:2: outcome \"unknown\" is none of passed, failed, stopped, invalid, "
            "set_up_failed");
  EXPECT_EQ(ErrorOf(std::string(kHeader) + good + two_line + good),
            "base/runs.csv:5: case 0 again, first on line 2");
  EXPECT_EQ(ErrorOf(std::string(kHeader) + good + "1,hover,2,0.5,1,failed,0,0,0,\"cut\n"),
            "base/runs.csv:3: field 10 opens a quote that never closes");
  EXPECT_EQ(ErrorOf(std::string(kHeader) + "0,\"hover\"x,1,0.5,1,passed,1,0,0,,1,1\n"),
            "base/runs.csv:2: field 2 has text after its closing quote");
  EXPECT_EQ(ErrorOf("case,scenario,outcome\n0,hover,passed\n"),
            "base/runs.csv:1: not the header of a sweep's runs.csv: it starts case,scenario,seed, "
            "then a column per axis and outcome");
  EXPECT_EQ(ErrorOf(""), "base/runs.csv: empty, without even a header line");
  EXPECT_EQ(ErrorOf(std::string(kHeader) + good + std::string(kMaxRunsCsvLineBytes + 1, 'x')),
            "base/runs.csv:3: a line longer than 1048576 bytes");
}

TEST(RunsCsvTest, AFolderWithoutARegularRunsCsvIsNamed) {
  const std::filesystem::path dir = FreshTestDir("runs_csv_missing");
  const auto missing = ReadRunsCsv(dir.string());
  ASSERT_FALSE(missing.ok());
  EXPECT_THAT(missing.error().message, HasSubstr((dir / "runs.csv").string()));
  std::filesystem::create_directory(dir / "runs.csv");
  const auto folder = ReadRunsCsv(dir.string());
  ASSERT_FALSE(folder.ok());
  EXPECT_THAT(folder.error().message, HasSubstr("not a regular file"));

  const std::filesystem::path good = FreshTestDir("runs_csv_file");
  std::ofstream(good / "runs.csv") << kHeader << "0,hover,1,0.5,1,passed,1,0,0,,1,1\n"
                                   << "1,hover,1,0.5,1,passe,1,0,0,,1,1\n";
  const auto damaged = ReadRunsCsv(good.string());
  ASSERT_FALSE(damaged.ok());
  EXPECT_EQ(damaged.error().message, (good / "runs.csv").string() +
                                         ":3: outcome \"passe\" is none of passed, failed, "
                                         "stopped, invalid, set_up_failed");
}

}  // namespace
}  // namespace hilrig::host
