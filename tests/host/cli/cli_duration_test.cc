// `hilrig run --duration-s S`: only the scene's first S seconds run, with the timeline entries that
// lie beyond them left out. An envelope whose window opens after the end is not evaluated, and says
// so on the terminal, in report.json and in junit.xml: a shortened run never passes on envelopes it
// could not check.
#include <gtest/gtest.h>

#include "host/cli/cli.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

const std::string kLoadRamp =
    ::hilrig::test_support::SourceDir() + "/scenarios/load_ramp.textproto";

TEST(CliDurationTest, AShortenedSceneNamesTheEnvelopesItCouldNotEvaluateAndDoesNotPass) {
  const std::string out = ::testing::TempDir() + "/cli_duration_short";
  const CliResult run =
      Cli({"run", kLoadRamp, "--duration-s", "18", "--no-reference", "--out", out});
  EXPECT_EQ(run.exit_code, kExitCheckFailed) << run.out << run.err;
  EXPECT_NE(run.out.find("18 s simulated"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("PASS  initial_load"), std::string::npos) << run.out;
  // The envelopes that open at 36 s saw no sample.
  EXPECT_NE(run.out.find("NOT EVALUATED  final_load  no samples in its window"), std::string::npos)
      << run.out;
  const std::string report = ReadFile(out + "/report.json");
  EXPECT_NE(report.find("\"not_evaluated\": true"), std::string::npos) << report;
  EXPECT_NE(report.find("\"passed\": false"), std::string::npos);
  const std::string junit = ReadFile(out + "/junit.xml");
  EXPECT_NE(junit.find("name=\"final_load\">\n      <failure message=\"NOT EVALUATED"),
            std::string::npos)
      << junit;
}

TEST(CliDurationTest, ADurationPastTheSceneRunsAllOfIt) {
  const std::string out = ::testing::TempDir() + "/cli_duration_long";
  const CliResult run =
      Cli({"run", kLoadRamp, "--duration-s", "100", "--no-reference", "--out", out});
  ASSERT_EQ(run.exit_code, kExitPass) << run.out << run.err;
  EXPECT_NE(run.out.find("45 s simulated"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("final_load"), std::string::npos) << run.out;
}

TEST(CliDurationTest, ABadDurationExitsTwoNamingIt) {
  for (const char* text : {"0", "-3", "nan", "inf", "5s", ""}) {
    const CliResult run = Cli({"run", kLoadRamp, "--duration-s", text});
    EXPECT_EQ(run.exit_code, kExitBadInput) << text;
    EXPECT_NE(run.err.find("--duration-s must be a positive number of seconds"), std::string::npos)
        << run.err;
  }
}

}  // namespace
}  // namespace hilrig::host
