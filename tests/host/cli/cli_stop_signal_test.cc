// Every hilrig command stops within a second of Ctrl-C (SIGINT) or SIGTERM and writes out what it
// finished: `decode` waiting on an open pipe, `accuracy` and `calibrate` in the middle of their
// bench readings. Real processes: the hilrig binary, signalled once it has its handlers.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/child_waits.h"
#include "tests/support/shared_calibration.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// The time a stopped command has to exit.
constexpr double kStopDeadlineS = 1.0;

class CliStopSignalTest : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override { dir_ = FreshTestDir("cli_stop_signal_"); }
  std::string Redirected() const {
    return " > " + (dir_ / "out").string() + " 2> " + (dir_ / "err").string();
  }
  // Signals the child once it is `hilrig` with its handlers in place and has used `cpu_s` of
  // CPU time (in the middle of its work), and returns how it ended within kStopDeadlineS.
  std::optional<std::string> StopAfter(ChildProcess& child, double cpu_s) {
    EXPECT_TRUE(WaitUntil(
        [&] {
          return CatchesSignal(child.pid(), "hilrig", GetParam()) &&
                 CpuSeconds(child.pid()) >= cpu_s;
        },
        60))
        << ReadFile(dir_ / "err");
    EXPECT_FALSE(child.PollExit()) << "ended before it was signalled: " << ReadFile(dir_ / "err");
    EXPECT_EQ(::kill(child.pid(), GetParam()), 0);
    return WaitForExit(child, kStopDeadlineS);
  }

  fs::path dir_;
};

// decode reads its standard input from a pipe whose writer stays: it waits for lines that never
// come, and a signal ends the wait. The line sent before was decoded and is in its output.
TEST_P(CliStopSignalTest, DecodeWaitingOnAnOpenPipeStops) {
  const fs::path fifo = dir_ / "stdin";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int writer = ::open(fifo.c_str(), O_RDWR);  // a writer that never closes
  ASSERT_GE(writer, 0);
  ChildProcess child =
      StartShellCommand(HilrigBinary() + " decode --calibration " + SharedCalibrationFile() +
                        " < " + fifo.string() + Redirected());
  const std::string line = "0 0 0.003\n";
  ASSERT_EQ(::write(writer, line.data(), line.size()), static_cast<ssize_t>(line.size()));
  // Read by decode: nothing left in the pipe.
  ASSERT_TRUE(WaitUntil(
      [&] {
        int unread = -1;
        return ::ioctl(writer, FIONREAD, &unread) == 0 && unread == 0;
      },
      60));

  EXPECT_EQ(StopAfter(child, 0), "exited with status 1");
  ::close(writer);
  EXPECT_THAT(ReadFile(dir_ / "err"), HasSubstr("hilrig decode: interrupted"));
  const std::string out = ReadFile(dir_ / "out");
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
}

// The held-out sweep takes about 8 s of bench readings at tiles:32.
TEST_P(CliStopSignalTest, AccuracyStopsInTheMiddleOfItsSweepAndWritesNothing) {
  ChildProcess child =
      StartShellCommand(HilrigBinary() + " accuracy --calibration " + SharedCalibrationFile() +
                        " --out " + (dir_ / "accuracy").string() + Redirected());
  EXPECT_EQ(StopAfter(child, 0.3), "exited with status 1");
  EXPECT_THAT(ReadFile(dir_ / "err"), HasSubstr("hilrig accuracy: interrupted, nothing written"));
  EXPECT_FALSE(fs::exists(dir_ / "accuracy" / "accuracy.json"));
}

// At tiles:128 the compensation fit's field samples (729 poses) take about 10 s and each node's
// jigs about 45 s: 1 s of CPU is inside the first stage, whose end is far beyond the deadline.
TEST_P(CliStopSignalTest, CalibrateStopsInTheMiddleOfAStageAndWritesNothing) {
  ChildProcess child = StartShellCommand(HilrigBinary() + " calibrate --field tiles:128 --out " +
                                         (dir_ / "calibration").string() + Redirected());
  EXPECT_EQ(StopAfter(child, 1.0), "exited with status 1");
  EXPECT_THAT(ReadFile(dir_ / "err"), HasSubstr("hilrig calibrate: interrupted, nothing written"));
  EXPECT_FALSE(fs::exists(dir_ / "calibration" / "calibration.textproto"));
}

// A map:128 film tabulates for about 24 s before a run's first tick (once per build, then from
// the cache): 1 s of CPU is inside it. The run is cut short, fails as an interrupted run and its
// folder says so.
TEST_P(CliStopSignalTest, RunStopsWhileTabulatingAFieldMap) {
  std::string spec = ReadFile(fs::path(::hilrig::test_support::SourceDir()) / "scenarios" /
                              "tactile_hover.textproto");
  const std::string level = "field_fidelity: \"tiles:8\"";
  ASSERT_NE(spec.find(level), std::string::npos);
  spec.replace(spec.find(level), level.size(), "field_fidelity: \"map:128\"");
  std::ofstream(dir_ / "map128.textproto") << spec;
  ChildProcess child =
      StartShellCommand(HilrigBinary() + " run " + (dir_ / "map128.textproto").string() +
                        " --no-reference" + " --reference-cache " + (dir_ / "cache").string() +
                        " --out " + (dir_ / "run").string() + Redirected());
  // Interrupted, as a run is: exit 1, not the bad input's 2.
  EXPECT_EQ(StopAfter(child, 1.0), "exited with status 1");
  EXPECT_THAT(ReadFile(dir_ / "err"), HasSubstr("interrupted while tabulating the map:128"));
  EXPECT_THAT(ReadFile(dir_ / "run" / "report.json"), HasSubstr("\"stop_reason\": \"incomplete\""));
}

INSTANTIATE_TEST_SUITE_P(SigintAndSigterm, CliStopSignalTest, ::testing::Values(SIGINT, SIGTERM),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return info.param == SIGINT ? std::string("Sigint")
                                                       : std::string("Sigterm");
                         });

}  // namespace
}  // namespace hilrig::host
