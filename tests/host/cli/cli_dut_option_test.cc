// `hilrig run --dut inproc|process [--dut-timeout-s S]`: the option's parsing and its errors. The
// full process run is covered by tests/host/dut/process_dut_acceptance_test.cc.
#include <gtest/gtest.h>

#include <sstream>

#include "host/cli/cli.h"
#include "tests/support/cli_runner.h"

namespace hilrig::host {
namespace {

const std::string kScenario = HILRIG_SOURCE_DIR "/scenarios/hover.textproto";

TEST(CliDutOptionTest, UnknownDutModeExitsTwoNamingIt) {
  const CliResult run = Cli({"run", kScenario, "--dut", "remote"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("--dut \"remote\": expected inproc or process"), std::string::npos)
      << run.err;
}

TEST(CliDutOptionTest, TimeoutWithoutProcessModeExitsTwo) {
  const CliResult run = Cli({"run", kScenario, "--dut-timeout-s", "2"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("--dut-timeout-s needs --dut process"), std::string::npos) << run.err;
}

TEST(CliDutOptionTest, BadTimeoutsExitTwo) {
  for (const char* timeout : {"0", "-1", "nan", "inf", "1s", ""}) {
    const CliResult run = Cli({"run", kScenario, "--dut", "process", "--dut-timeout-s", timeout});
    EXPECT_EQ(run.exit_code, kExitBadInput) << timeout;
    EXPECT_NE(run.err.find("--dut-timeout-s"), std::string::npos) << run.err;
  }
}

}  // namespace
}  // namespace hilrig::host
