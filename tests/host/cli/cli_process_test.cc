// hilrig as a child process: standard output on a full device, and inputs that would block or
// exhaust the process (a FIFO, /dev/zero) given as a spec or a calibration.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include "host/cli/cli.h"
#include "tests/support/hilrig_process.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kHover = ::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto";
constexpr const char* kStdoutFull =
    "hilrig: cannot write to standard output: No space left on device";

// Six sensors with unit gains: enough for decode to answer every line.
std::string SyntheticCalibration() {
  std::string text = "film { k1: 1 c1: 0.001 k2: 1 c2: 0.002 }\n";
  for (int node = 1; node <= 6; ++node) {
    text += "sensors { node_id: " + std::to_string(node) +
            " a { x: 1 y: 1 z: 1 } b { x: 0 y: 0 z: 0 } }\n";
  }
  return text;
}

class CliProcessTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = FreshTestDir("hilrig_cli_process_"); }
  ProcessResult Hilrig(const std::string& arguments) {
    return RunHilrig(arguments, dir_ / "stderr.txt");
  }
  std::string Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  // `check` and `run` of one spec.
  std::vector<std::string> Commands(const std::string& spec) const {
    return {"check " + spec, "run " + spec + " --no-reference --out " + (dir_ / "out").string()};
  }
  std::string Fifo() {
    const fs::path fifo = dir_ / "pipe.textproto";
    EXPECT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    return fifo.string();
  }
  fs::path dir_;
};

TEST_F(CliProcessTest, CheckWithStandardOutputOnAFullDeviceFailsAndSaysWhy) {
  const ProcessResult result = Hilrig("check " + kHover + " >/dev/full");
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr(kStdoutFull));
}

TEST_F(CliProcessTest, RunWithStandardOutputOnAFullDeviceFailsButKeepsItsFiles) {
  const std::string spec = Write("short.textproto", R"(name: "short"
simulation { duration_s: 0.5 }
envelopes { name: "grounded" signal: ALTITUDE_M upper: 0.01 }
)");
  const ProcessResult result =
      Hilrig("run " + spec + " --no-reference --out " + (dir_ / "out").string() + " >/dev/full");
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr(kStdoutFull));
  EXPECT_THAT(ReadFile(dir_ / "out" / "report.json"), HasSubstr("\"stop_reason\": \"completed\""));
}

TEST_F(CliProcessTest, CalibrateWithStandardOutputOnAFullDeviceFailsButKeepsTheFile) {
  const ProcessResult result =
      Hilrig("calibrate --field map:16 --out " + (dir_ / "cal").string() + " >/dev/full");
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr(kStdoutFull));
  EXPECT_THAT(ReadFile(dir_ / "cal" / "calibration.textproto"), HasSubstr("node_id: 6"));
}

TEST_F(CliProcessTest, DecodeWithStandardOutputOnAFullDeviceFailsAndSaysWhy) {
  const std::string calibration = Write("calibration.textproto", SyntheticCalibration());
  const std::string readings = Write("readings.txt", "0 0 0.003\n0.0001 0 0.003\n");
  // The same input to a working standard output exits 0: the failure is the lost output.
  EXPECT_EQ(
      Hilrig("decode --calibration " + calibration + " <" + readings + " >/dev/null").exit_code,
      kExitPass);
  const ProcessResult result =
      Hilrig("decode --calibration " + calibration + " <" + readings + " >/dev/full");
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr(kStdoutFull));
}

TEST_F(CliProcessTest, AFifoAsASpecIsRefusedAtOnce) {
  const std::string fifo = Fifo();
  for (const std::string& command : Commands(fifo)) {
    const ProcessResult result = Hilrig(command);
    EXPECT_EQ(result.exit_code, kExitBadInput) << command;
    EXPECT_THAT(result.err, HasSubstr("cannot read " + fifo + ": a FIFO")) << command;
  }
}

TEST_F(CliProcessTest, DevZeroAsASpecIsRefusedAtOnce) {
  for (const std::string& command : Commands("/dev/zero")) {
    const ProcessResult result = Hilrig(command);
    EXPECT_EQ(result.exit_code, kExitBadInput) << command;
    EXPECT_THAT(result.err, HasSubstr("cannot read /dev/zero: a device")) << command;
  }
}

TEST_F(CliProcessTest, AFifoOrDevZeroAsACalibrationIsRefusedAtOnce) {
  const std::string fifo = Fifo();
  for (const std::string& calibration : {fifo, std::string("/dev/zero")}) {
    for (const std::string& command : {std::string("decode </dev/null"),
                                       "accuracy --field map:2 --out " + (dir_ / "acc").string()}) {
      const ProcessResult result = Hilrig(command + " --calibration " + calibration);
      EXPECT_EQ(result.exit_code, kExitBadInput) << command << calibration;
      EXPECT_THAT(result.err, HasSubstr("cannot read " + calibration + ": a "))
          << command << calibration;
    }
  }
}

}  // namespace
}  // namespace hilrig::host
