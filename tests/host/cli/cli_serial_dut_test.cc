// `hilrig run --dut serial:DEVICE[,baud=N][,bridge=DEVICE]` and `--dut qemu [--target-image ELF]`:
// the options' parsing and errors, and a device that does not open ending the run with a named
// stop reason. SerialDut itself is tested in tests/host/linked_dut/serial_dut_test.cc.
#include <gtest/gtest.h>

#include "host/cli/cli.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

const std::string kScenario = ::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto";

TEST(CliSerialDutTest, BadSerialSpecsExitTwoNamingThePart) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"serial:", "--dut \"serial:\": no device after serial:"},
      {"serial:/dev/a,baud=x", "--dut \"serial:/dev/a,baud=x\": baud \"x\" is not a whole number"},
      {"serial:/dev/a,stop=2", "--dut \"serial:/dev/a,stop=2\": unknown option \"stop=2\""},
  };
  for (const auto& [spec, message] : cases) {
    const CliResult run = Cli({"run", kScenario, "--dut", spec});
    EXPECT_EQ(run.exit_code, kExitBadInput) << spec;
    EXPECT_NE(run.err.find(message), std::string::npos) << run.err;
  }
}

TEST(CliSerialDutTest, TargetImageBelongsToQemuAndMustExist) {
  CliResult run = Cli({"run", kScenario, "--target-image", "/x.elf"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("--target-image needs --dut qemu"), std::string::npos) << run.err;
  run = Cli({"run", kScenario, "--dut", "serial:/dev/a", "--target-image", "/x.elf"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("--target-image needs --dut qemu"), std::string::npos) << run.err;
  run = Cli({"run", kScenario, "--dut", "qemu", "--target-image", "/nonexistent/fw.elf"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("--dut qemu: no target image at /nonexistent/fw.elf"), std::string::npos)
      << run.err;
}

TEST(CliSerialDutTest, TimeoutAppliesToSerialDutsAndIsChecked) {
  CliResult run = Cli({"run", kScenario, "--dut", "serial:/dev/a", "--dut-timeout-s", "0"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("--dut-timeout-s: dut answer timeout 0 s"), std::string::npos) << run.err;
  // QEMU's board has no CAN port; a board on serial devices may read its sensors on its own.
  run = Cli({"run", kScenario, "--dut", "qemu", "--can", "socketcan:vcan0"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("needs --dut process, exec: or serial:"), std::string::npos) << run.err;
  run = Cli({"run", kScenario, "--dut", "serial:/dev/a", "--can", "udp:4600:1:2"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("a run's dut bus is socketcan:IFACE"), std::string::npos) << run.err;
}

TEST(CliSerialDutTest, ADeviceThatDoesNotOpenStopsTheRunNamingIt) {
  const std::filesystem::path out = FreshTestDir("cli_serial_missing");
  const CliResult run = Cli({"run", kScenario, "--no-reference", "--out", out.string(), "--dut",
                             "serial:/dev/hilrig-no-such-tty,baud=115200"});
  EXPECT_EQ(run.exit_code, kExitCheckFailed);
  const std::string report = ReadFile(out / "report.json");
  EXPECT_NE(report.find("dut failed to start: serial port /dev/hilrig-no-such-tty: open: No such "
                        "file or directory"),
            std::string::npos)
      << report;
}

}  // namespace
}  // namespace hilrig::host
