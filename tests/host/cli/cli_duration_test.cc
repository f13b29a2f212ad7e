// `hilrig run --duration-s S`: only the scene's first S seconds run, with the timeline entries and
// envelopes that lie beyond them left out, so a shortened scene still has a verdict.
#include <gtest/gtest.h>

#include "host/cli/cli.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

const std::string kLoadRamp =
    ::hilrig::test_support::SourceDir() + "/scenarios/load_ramp.textproto";

TEST(CliDurationTest, AShortenedSceneRunsItsFirstSecondsAndPasses) {
  const std::string out = ::testing::TempDir() + "/cli_duration_short";
  const CliResult run =
      Cli({"run", kLoadRamp, "--duration-s", "18", "--no-reference", "--out", out});
  ASSERT_EQ(run.exit_code, kExitPass) << run.out << run.err;
  EXPECT_NE(run.out.find("18 s simulated"), std::string::npos) << run.out;
  // The envelopes that open at 36 s are not in the shortened scene.
  EXPECT_EQ(run.out.find("final_load"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("initial_load"), std::string::npos) << run.out;
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
