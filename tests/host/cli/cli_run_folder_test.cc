// `hilrig run` owns its output folder: a run killed in a folder used before leaves a report that
// says "incomplete", never the previous run's pass, and a second run into a folder in use is
// refused. Real processes: the hilrig binary, killed with SIGKILL or run twice at once.
#include <gmock/gmock.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "proto/report.pb.h"
#include "tests/support/child_waits.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Hover for a day of simulated time, a trace row a second: minutes of wall time, a small trace.
std::string LongHover() {
  std::string spec =
      ReadFile(fs::path(::hilrig::test_support::SourceDir()) / "scenarios" / "hover.textproto");
  const auto replace = [&spec](const std::string& from, const std::string& to) {
    const std::size_t at = spec.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) spec.replace(at, from.size(), to);
  };
  replace("duration_s: 40", "duration_s: 86400");
  replace("trace_rate_hz: 100", "trace_rate_hz: 1");
  return spec;
}

proto::Report ReadReport(const fs::path& path) {
  proto::Report report;
  const auto status = google::protobuf::util::JsonStringToMessage(ReadFile(path), &report);
  EXPECT_TRUE(status.ok()) << path << ": " << status.ToString();
  return report;
}

class CliRunFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshTestDir("cli_run_folder_");
    std::ofstream(dir_ / "long.textproto") << LongHover();
  }
  // `hilrig run SPEC --no-reference --out OUT` as a child, its output in LOG.
  ChildProcess Start(const fs::path& spec, const fs::path& out, const std::string& log) {
    return StartShellCommand(HilrigBinary() + " run " + spec.string() + " --no-reference --out " +
                             out.string() + " > " + (dir_ / log).string() + " 2>&1");
  }
  // The lock file of `out` names `child` as its holder.
  bool Holds(const ChildProcess& child, const fs::path& out) const {
    return ReadFile(out / ".hilrig.lock").rfind("pid " + std::to_string(child.pid()) + "\n", 0) ==
           0;
  }

  fs::path dir_;
};

TEST_F(CliRunFolderTest, ARunKilledInAUsedFolderLeavesAnIncompleteReportNotTheOldPass) {
  const fs::path out = dir_ / "out";
  ChildProcess previous =
      Start(fs::path(::hilrig::test_support::SourceDir()) / "scenarios" / "hover.textproto", out,
            "previous.log");
  ASSERT_EQ(WaitForExit(previous, 60), "exited with status 0") << ReadFile(dir_ / "previous.log");
  ASSERT_EQ(ReadReport(out / "report.json").stop_reason(), "completed");
  ASSERT_THAT(ReadFile(out / "junit.xml"), HasSubstr("failures=\"0\""));
  const std::uintmax_t previous_trace_bytes = fs::file_size(out / "trace.csv");

  ChildProcess killed = Start(dir_ / "long.textproto", out, "killed.log");
  // The new run has started writing: its trace replaced the previous one.
  ASSERT_TRUE(WaitUntil(
      [&] {
        std::error_code error;
        return fs::file_size(out / "trace.csv", error) < previous_trace_bytes;
      },
      60));
  // Its first flush, a few wall seconds in, records how far it got.
  const bool reached = WaitUntil(
      [&] { return ReadReport(out / "report.json").simulated_s() > 0 && Holds(killed, out); }, 30);
  ASSERT_EQ(::kill(killed.pid(), SIGKILL), 0);
  ASSERT_EQ(WaitForExit(killed, 10), "killed by signal 9");

  const proto::Report report = ReadReport(out / "report.json");
  EXPECT_EQ(report.stop_reason(), "incomplete");
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(report.spec_file(), (dir_ / "long.textproto").string());
  EXPECT_TRUE(reached) << "no progress recorded before the kill";
  EXPECT_GT(report.simulated_s(), 0);
  EXPECT_LT(report.simulated_s(), 86400);
  const std::string junit = ReadFile(out / "junit.xml");
  EXPECT_THAT(junit, HasSubstr("failures=\"1\""));
  EXPECT_THAT(junit, HasSubstr("<failure message=\"incomplete at "));
  EXPECT_THAT(ReadFile(out / "index.html"), HasSubstr(">INCOMPLETE</span>"));
  EXPECT_FALSE(fs::exists(out / "position.svg")) << "the previous run's plot";
}

TEST_F(CliRunFolderTest, ASecondRunIntoAFolderInUseIsRefusedNamingTheFirst) {
  const fs::path out = dir_ / "out";
  ChildProcess first = Start(dir_ / "long.textproto", out, "first.log");
  // Its CAN log is made once the folder is its own.
  ASSERT_TRUE(WaitUntil([&] { return fs::exists(out / "can.log"); }, 30))
      << ReadFile(dir_ / "first.log");
  EXPECT_TRUE(Holds(first, out));

  ChildProcess second = Start(dir_ / "long.textproto", out, "second.log");
  EXPECT_EQ(WaitForExit(second, 10), "exited with status 2");
  EXPECT_THAT(ReadFile(dir_ / "second.log"),
              HasSubstr(out.string() + " is in use by another hilrig process: pid " +
                        std::to_string(first.pid()) + " ("));

  // The first carries on alone; stopped, it writes a report and a trace of its own, whole.
  ASSERT_FALSE(first.PollExit()) << ReadFile(dir_ / "first.log");
  ASSERT_EQ(::kill(first.pid(), SIGTERM), 0);
  ASSERT_EQ(WaitForExit(first, 10), "exited with status 1") << ReadFile(dir_ / "first.log");
  const proto::Report report = ReadReport(out / "report.json");
  EXPECT_EQ(report.stop_reason(), "interrupted");
  const std::string trace = ReadFile(out / "trace.csv");
  const std::string header = trace.substr(0, trace.find('\n') + 1);
  EXPECT_EQ(trace.find(header, 1), std::string::npos) << "a second trace spliced in";
  const auto rows = std::count(trace.begin(), trace.end(), '\n') - 1;
  EXPECT_EQ(rows, static_cast<long>(report.simulated_s()));  // a row per simulated second
}

// A folder run takes its whole output root: two of them would run the same scenarios into the
// same folders.
TEST_F(CliRunFolderTest, ASecondFolderRunIntoTheSameRootIsRefused) {
  const fs::path out = dir_ / "out";
  ChildProcess first =
      StartShellCommand(HilrigBinary() + " run " + dir_.string() + " --no-reference --out " +
                        out.string() + " > " + (dir_ / "first.log").string() + " 2>&1");
  ASSERT_TRUE(WaitUntil([&] { return fs::exists(out / "long" / "can.log"); }, 30))
      << ReadFile(dir_ / "first.log");
  EXPECT_TRUE(Holds(first, out));

  ChildProcess second =
      StartShellCommand(HilrigBinary() + " run " + dir_.string() + " --no-reference --out " +
                        out.string() + " > " + (dir_ / "second.log").string() + " 2>&1");
  EXPECT_EQ(WaitForExit(second, 10), "exited with status 2");
  EXPECT_THAT(ReadFile(dir_ / "second.log"), HasSubstr("pid " + std::to_string(first.pid())));
  EXPECT_EQ(ReadReport(out / "long" / "report.json").stop_reason(), "incomplete");
}

}  // namespace
}  // namespace hilrig::host
