// Acceptance of the real-time mode (issue 7): `hilrig run scenarios/bench/realtime_60s.textproto
// --realtime --dut process` runs a minute of wall time with the DUT in its own process, passes
// the scene's loose timing envelopes and its force/position envelopes, and report.json carries
// plausible timing figures. Not a *_test.cc: tests/CMakeLists.txt builds it on its own, labelled
// "realtime" and RUN_SERIAL, because it measures the machine (~60 s) and must run alone.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "proto/report.pb.h"
#include "tests/support/test_files.h"

namespace {

namespace fs = std::filesystem;

using hilrig::host::ReadFile;

TEST(RealtimeAcceptanceTest, SixtySecondsOnTheBenchPassWithTimingFigures) {
  const fs::path out =
      fs::temp_directory_path() / ("hilrig_realtime_" + std::to_string(::getpid()));
  const std::string command = std::string(HILRIG_BIN_DIR) + "/hilrig run " + HILRIG_SOURCE_DIR +
                              "/scenarios/bench/realtime_60s.textproto --realtime --dut process" +
                              " --out " + out.string() + " > " + out.string() + ".log 2>&1";

  const int status = std::system(command.c_str());

  const std::string log = ReadFile(out.string() + ".log");
  ASSERT_EQ(status, 0) << log;
  hilrig::proto::Report report;
  ASSERT_TRUE(
      google::protobuf::util::JsonStringToMessage(ReadFile(out / "report.json"), &report).ok());
  const hilrig::proto::Timing& timing = report.timing();
  EXPECT_EQ(report.stop_reason(), "completed");
  EXPECT_EQ(timing.mode(), "realtime");
  EXPECT_EQ(timing.ticks(), 60'000u);
  EXPECT_EQ(timing.ticks(), report.ticks());
  EXPECT_EQ(timing.control_ticks(), 60'000u);
  EXPECT_NEAR(timing.loop_period_p50_s(), 0.001, 0.0001);
  EXPECT_LE(timing.loop_period_p99_s(), timing.loop_period_max_s());
  // A tick's work fits its period at the median; its tail is the machine's (a descheduled vCPU).
  EXPECT_LE(timing.work_p50_s(), timing.period_s());
  EXPECT_GE(report.wall_s(), 59.99);
  EXPECT_LT(report.wall_s(), 61.0);
  EXPECT_GT(timing.dut_latency_size(), 0) << "the process DUT measures its response latency";
  for (const auto& stream : timing.dut_latency()) {
    EXPECT_GT(stream.count(), 0u) << stream.stream();
    EXPECT_LE(stream.p50_s(), stream.p99_s()) << stream.stream();
  }
  EXPECT_GE(report.timing_checks_size(), 5);
  for (const auto& check : report.timing_checks()) {
    EXPECT_TRUE(check.evaluated()) << check.name() << ": " << check.note();
    EXPECT_TRUE(check.passed()) << check.name() << " " << check.value();
  }
  EXPECT_NE(log.find("loop period p50"), std::string::npos) << log;
  fs::remove_all(out);
  fs::remove(out.string() + ".log");
}

}  // namespace
