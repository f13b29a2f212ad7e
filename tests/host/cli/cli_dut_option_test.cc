// `hilrig run --dut inproc|inproc-float|process [--dut-timeout-s S] [--dut-link shm|tcp]
// [--can URI]`: the options' parsing and their errors. The full process run is covered by
// tests/host/linked_dut/process_dut_acceptance_test.cc, a bus named by --can by
// tests/host/linked_dut/process_dut_can_test.cc.
#include <gtest/gtest.h>

#include <sstream>

#include "host/cli/cli.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

const std::string kScenario = ::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto";

TEST(CliDutOptionTest, UnknownDutModeExitsTwoNamingIt) {
  const CliResult run = Cli({"run", kScenario, "--dut", "remote"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("--dut \"remote\": expected inproc, inproc-float, process, "
                         "exec:PROGRAM[,ARG...], listen:ADDRESS:PORT[,token=FILE], qemu, "
                         "serial:"),
            std::string::npos)
      << run.err;
}

TEST(CliDutOptionTest, DutLinkNeedsProcessModeAndAKnownTransport) {
  const CliResult inproc = Cli({"run", kScenario, "--dut-link", "tcp"});
  EXPECT_EQ(inproc.exit_code, kExitBadInput);
  EXPECT_NE(inproc.err.find("--dut-link needs --dut process"), std::string::npos) << inproc.err;
  const CliResult unknown = Cli({"run", kScenario, "--dut", "process", "--dut-link", "udp"});
  EXPECT_EQ(unknown.exit_code, kExitBadInput);
  EXPECT_NE(unknown.err.find("--dut-link \"udp\": expected shm, tcp or line"), std::string::npos)
      << unknown.err;
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

TEST(CliDutOptionTest, CanWithoutProcessModeExitsTwo) {
  for (const char* mode : {"", "inproc", "inproc-float"}) {
    std::vector<std::string> args = {"run", kScenario, "--can", "socketcan:vcan0"};
    if (*mode != '\0') args.insert(args.end(), {"--dut", mode});
    const CliResult run = Cli(args);
    EXPECT_EQ(run.exit_code, kExitBadInput) << mode;
    EXPECT_NE(run.err.find("--can socketcan:vcan0 needs --dut process"), std::string::npos)
        << run.err;
  }
}

// Errors name the URI and the cause: rig::ParseCanBusUri's for a URI it cannot read, and for the
// buses it reads why a run's DUT process cannot share them.
TEST(CliDutOptionTest, UnusableCanBusExitsTwoNamingItAndWhy) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"serial:/dev/ttyUSB0", "unknown scheme \"serial\"; expected emulated"},
      {"socketcan", "expected socketcan:IFACE with one interface name"},
      {"udp:30000:1:2", "the rig chooses the run's own UDP bus to the dut process itself"},
      {"emulated", "an emulated bus lives inside one process"},
      {"gs_usb", "one process claims a gs_usb adapter over libusb"},
  };
  for (const auto& [uri, why] : cases) {
    const CliResult run = Cli({"run", kScenario, "--dut", "process", "--can", uri});
    EXPECT_EQ(run.exit_code, kExitBadInput) << uri;
    EXPECT_NE(run.err.find("--can: CAN bus \"" + uri + "\": " + why), std::string::npos) << run.err;
  }
}

// The interface is opened when the run starts its DUT: one that cannot be opened is a DUT that
// failed to start, which cuts the run short (exit 1) with the URI and the cause in its stop reason.
TEST(CliDutOptionTest, AnInterfaceThatCannotOpenStopsTheRunNamingIt) {
  const CliResult run = Cli({"run", kScenario, "--dut", "process", "--can", "socketcan:hilrignone0",
                             "--no-reference", "--out", ::testing::TempDir() + "/cli_can_none"});
  EXPECT_EQ(run.exit_code, kExitCheckFailed);
  EXPECT_NE(run.out.find("dut failed to start: CAN bus \"socketcan:hilrignone0\": "),
            std::string::npos)
      << run.out;
}

// A program of the user's in dut_emu's place (dut_emu itself here, which speaks the link, with an
// argument of its own): the scene's first two seconds fly to the end as with --dut process (the
// take-off passes; the later envelopes are not reached), and the report names the program.
TEST(CliDutOptionTest, ExecFliesTheSceneWithAProgramInDutEmusPlace) {
  const std::string program = ::hilrig::test_support::BinDir() + "/dut_emu";
  const std::string out = ::testing::TempDir() + "/cli_exec";
  for (const std::string link : {"shm", "tcp"}) {
    const CliResult run =
        Cli({"run", kScenario, "--dut", "exec:" + program + ",--frame-timeout-ms,2000",
             "--dut-link", link, "--no-reference", "--duration-s", "2", "--out", out + link});
    EXPECT_NE(run.out.find("PASS  takeoff_position_error"), std::string::npos) << link << run.out;
    EXPECT_NE(run.out.find("2 s simulated in"), std::string::npos) << link << run.out;
    EXPECT_NE(run.out.find(" wall, completed;"), std::string::npos) << link << run.out;
    EXPECT_NE(ReadFile(out + link + "/report.json").find("the program " + program),
              std::string::npos);
  }
  const CliResult missing =
      Cli({"run", kScenario, "--dut", "exec:/nonexistent/my_dut", "--no-reference", "--out", out});
  EXPECT_EQ(missing.exit_code, kExitCheckFailed);
  EXPECT_NE(missing.out.find("dut failed to start: no executable program at /nonexistent/my_dut"),
            std::string::npos)
      << missing.out;
}

// The single-precision firmware is the one a target runs: the same scene flies, but its trace is
// not the double one's byte for byte.
TEST(CliDutOptionTest, InprocFloatRunsTheFirmwareInSinglePrecision) {
  const std::string out = ::testing::TempDir() + "/cli_inproc_float";
  const CliResult single =
      Cli({"run", kScenario, "--dut", "inproc-float", "--no-reference", "--out", out + "/float"});
  ASSERT_EQ(single.exit_code, kExitPass) << single.out << single.err;
  const CliResult twice = Cli({"run", kScenario, "--no-reference", "--out", out + "/double"});
  ASSERT_EQ(twice.exit_code, kExitPass) << twice.out << twice.err;
  EXPECT_NE(ReadFile(out + "/float/report.json").find("in-process dut_fw (float)"),
            std::string::npos);
  EXPECT_NE(ReadFile(out + "/float/trace.csv"), ReadFile(out + "/double/trace.csv"));
}

}  // namespace
}  // namespace hilrig::host
