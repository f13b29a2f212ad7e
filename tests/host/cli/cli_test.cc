#include "host/cli/cli.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "rig/candump_log.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kHover = ::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto";

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = FreshTestDir("hilrig_cli_"); }
  fs::path WriteSpec(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path;
  }
  fs::path dir_;
};

TEST_F(CliTest, HoverPassesAndWritesEveryOutput) {
  const CliResult result = Cli({"run", kHover, "--out", (dir_ / "out").string()});
  ASSERT_EQ(result.exit_code, kExitPass) << result.out << result.err;
  for (const char* file : {"report.json", "junit.xml", "trace.csv", "can.log"}) {
    EXPECT_GT(fs::file_size(dir_ / "out" / file), 0u) << file;
  }
  EXPECT_THAT(result.out, HasSubstr("PASS  hover_position_error"));
  EXPECT_THAT(result.out, HasSubstr("real-time factor"));
  EXPECT_THAT(ReadFile(dir_ / "out" / "trace.csv"), ::testing::StartsWith("time_s,x_m,y_m,z_m"));
  EXPECT_THAT(ReadFile(dir_ / "out" / "report.json"), HasSubstr("\"real_time_factor\""));
}

TEST_F(CliTest, SameSeedGivesByteIdenticalTraceAndCanLog) {
  ASSERT_EQ(Cli({"run", kHover, "--out", (dir_ / "a").string(), "--seed", "7"}).exit_code, 0);
  ASSERT_EQ(Cli({"run", kHover, "--out", (dir_ / "b").string(), "--seed", "7"}).exit_code, 0);
  EXPECT_EQ(ReadFile(dir_ / "a" / "trace.csv"), ReadFile(dir_ / "b" / "trace.csv"));
  EXPECT_EQ(ReadFile(dir_ / "a" / "can.log"), ReadFile(dir_ / "b" / "can.log"));
}

TEST_F(CliTest, OtherSeedChangesTheNoiseAndStillPasses) {
  ASSERT_EQ(Cli({"run", kHover, "--out", (dir_ / "a").string(), "--seed", "1"}).exit_code, 0);
  const CliResult other = Cli({"run", kHover, "--out", (dir_ / "b").string(), "--seed", "2"});
  EXPECT_EQ(other.exit_code, kExitPass) << other.out;
  EXPECT_NE(ReadFile(dir_ / "a" / "trace.csv"), ReadFile(dir_ / "b" / "trace.csv"));
  EXPECT_NE(ReadFile(dir_ / "a" / "can.log"), ReadFile(dir_ / "b" / "can.log"));
}

TEST_F(CliTest, CanLogParsesAndCountsWhatTheReportSays) {
  ASSERT_EQ(Cli({"run", kHover, "--out", dir_.string()}).exit_code, 0);
  std::istringstream log(ReadFile(dir_ / "can.log"));
  std::string line;
  int frames = 0;
  while (std::getline(log, line)) {
    ASSERT_TRUE(rig::ParseCandumpLine(line).ok()) << line;
    ++frames;
  }
  // Reference node for 40 s: samples at 50 Hz and its status frame at 1 Hz.
  EXPECT_EQ(frames, 2040);
  EXPECT_THAT(ReadFile(dir_ / "report.json"),
              HasSubstr("\"can_frames_logged\": \"" + std::to_string(frames) + "\""));
}

TEST_F(CliTest, FailedEnvelopeExitsOne) {
  const fs::path spec = WriteSpec("tight.textproto", R"(name: "tight"
simulation { duration_s: 2 }
timeline { at_s: 0 setpoint { position_m { z: 1 } transition_s: 1 } }
envelopes { name: "impossible" signal: ALTITUDE_ERROR_M upper: 0.0001 }
)");
  const CliResult result = Cli({"run", spec.string(), "--out", (dir_ / "out").string()});
  EXPECT_EQ(result.exit_code, kExitCheckFailed);
  EXPECT_THAT(result.out, HasSubstr("FAIL  impossible"));
  EXPECT_THAT(ReadFile(dir_ / "out" / "junit.xml"), HasSubstr("<failure"));
}

TEST_F(CliTest, ExpectedFailureThatHappensPasses) {
  const fs::path spec = WriteSpec("expect_fail.textproto", R"(name: "expect_fail"
simulation { duration_s: 2 }
envelopes { name: "stays_on_ground" signal: ALTITUDE_M upper: 0.5 expect: FAIL }
timeline { at_s: 0 setpoint { position_m { z: 1 } transition_s: 1 } }
)");
  EXPECT_EQ(Cli({"run", spec.string(), "--out", (dir_ / "out").string()}).exit_code, kExitPass);
}

TEST_F(CliTest, MalformedSpecsExitTwoNamingTheProblem) {
  struct Case {
    std::string text;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"name: \"x\"\nsimulation { duration_s: 1\n", "bad.textproto:3:1"},
      {"name: \"x\"\nsimulation { duration_s: 1 }\nvehicle { mass: 1 }\n", "mass"},
      {"name: \"x\"\nsimulation { duration_s: 1 }\nvehicle { mass_kg: -1 }\n",
       "bad.textproto:3:11: vehicle.mass_kg: must be > 0"},
      {"name: \"x\"\nsimulation { duration_s: 1 }\nenvelopes { name: \"e\" signal: TILT_DEG }\n",
       "bad.textproto:3:1: envelopes[0]: needs a limit"},
  };
  for (const Case& test_case : cases) {
    const fs::path spec = WriteSpec("bad.textproto", test_case.text);
    const CliResult result = Cli({"run", spec.string(), "--out", (dir_ / "out").string()});
    EXPECT_EQ(result.exit_code, kExitBadInput) << test_case.text;
    EXPECT_THAT(result.err, HasSubstr(test_case.expected)) << result.err;
    EXPECT_EQ(Cli({"check", spec.string()}).exit_code, kExitBadInput);
  }
}

TEST_F(CliTest, MissingCalibrationFileExitsTwo) {
  const fs::path spec = WriteSpec("pads.textproto", R"(name: "pads"
simulation { duration_s: 1 }
models { tactile { enabled: true calibration_file: "nowhere/calibration.textproto" } }
envelopes { name: "alt" signal: ALTITUDE_M upper: 2 }
)");
  const CliResult result = Cli({"run", spec.string(), "--out", (dir_ / "out").string()});
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err,
              HasSubstr("cannot read " + (dir_ / "nowhere/calibration.textproto").string() +
                        ": No such file or directory"));
}

TEST_F(CliTest, ACalibrationFileThatIsNotOneIsRefusedWithoutQuotingIt) {
  {
    std::ofstream secret(dir_ / "secret.txt");
    secret << "hunter2secret: the first word a parse error would quote\n";
  }
  for (const std::string& calibration :
       {(dir_ / "secret.txt").string(), std::string("/dev/zero")}) {
    const fs::path spec = WriteSpec("pads.textproto", R"(name: "pads"
simulation { duration_s: 1 }
models { tactile { enabled: true calibration_file: ")" + calibration +
                                                          R"(" } }
envelopes { name: "alt" signal: ALTITUDE_M upper: 2 }
)");
    // Protobuf's parser logs what it stumbled on to the process's stderr, beside the command's.
    ::testing::internal::CaptureStderr();
    const CliResult result = Cli({"run", spec.string(), "--out", (dir_ / "out").string()});
    const std::string logged = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(result.exit_code, kExitBadInput) << calibration;
    EXPECT_THAT(result.err, HasSubstr(calibration)) << result.err;
    EXPECT_THAT(result.err + logged, Not(HasSubstr("hunter2secret"))) << result.err << logged;
  }
}

TEST_F(CliTest, MissingFileExitsTwo) {
  const CliResult result = Cli({"run", (dir_ / "nope.textproto").string()});
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.err, HasSubstr("nope.textproto: no such file"));
}

TEST_F(CliTest, UsageErrorsExitTwo) {
  EXPECT_EQ(Cli({}).exit_code, kExitBadInput);
  EXPECT_EQ(Cli({"fly"}).exit_code, kExitBadInput);
  EXPECT_EQ(Cli({"run", kHover, "--seed", "abc"}).exit_code, kExitBadInput);
  EXPECT_EQ(Cli({"run", kHover, "--frobnicate"}).exit_code, kExitBadInput);
  EXPECT_EQ(Cli({"run"}).exit_code, kExitBadInput);
}

TEST_F(CliTest, CheckAcceptsTheShippedScenario) {
  const CliResult result = Cli({"check", kHover});
  EXPECT_EQ(result.exit_code, kExitPass) << result.err;
  EXPECT_THAT(result.out, HasSubstr("ok"));
}

TEST_F(CliTest, FolderRunPrintsSummaryAndWorstExitCode) {
  WriteSpec("a_good.textproto", R"(name: "a_good"
simulation { duration_s: 1 }
envelopes { name: "grounded" signal: ALTITUDE_M upper: 0.01 }
)");
  WriteSpec("b_bad.textproto", "name: \"b\"\nsimulation { duration_s: -1 }\n");
  const CliResult result = Cli({"run", dir_.string(), "--out", (dir_ / "out").string()});
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_THAT(result.out, HasSubstr("a_good"));
  EXPECT_THAT(result.out, HasSubstr("INVALID"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "a_good" / "report.json"));
  EXPECT_THAT(result.out, HasSubstr("summary page: " + (dir_ / "out" / "index.html").string()));
  // The folder's page: each file's row, the one that ran linked to its own page.
  const std::string page = ReadFile(dir_ / "out" / "index.html");
  EXPECT_THAT(page, HasSubstr("<span class=\"badge fail\">FAIL</span>"));
  EXPECT_THAT(page, HasSubstr("2 of 2 scenario files run, 1 passed"));
  EXPECT_THAT(page, HasSubstr("<a href=\"a_good/index.html\">a_good</a>"));
  EXPECT_THAT(page, HasSubstr("<td>b_bad</td><td class=\"fail\">INVALID</td>"
                              "<td colspan=\"3\">did not run: "));
}

TEST_F(CliTest, AStoppedFolderRunSaysHowManyFilesRan) {
  WriteSpec("a.textproto", "name: \"a\"\nsimulation { duration_s: 1 }\n");
  WriteSpec("b.textproto", "name: \"b\"\nsimulation { duration_s: 1 }\n");
  std::atomic<bool> stop{true};
  std::ostringstream out, err;
  const int exit_code =
      RunCli({"run", dir_.string(), "--out", (dir_ / "out").string()}, out, err, &stop);
  EXPECT_EQ(exit_code, kExitCheckFailed);
  EXPECT_THAT(out.str(), HasSubstr("INCOMPLETE (stopped): 0 of 2 scenario files ran"));
  const std::string page = ReadFile(dir_ / "out" / "index.html");
  EXPECT_THAT(page, HasSubstr("<span class=\"badge neutral\">INCOMPLETE</span>"));
  EXPECT_THAT(page, HasSubstr("0 of 2 scenario files run"));
}

TEST_F(CliTest, StopRequestEndsTheRunWithACompleteReport) {
  std::atomic<bool> stop{true};
  std::ostringstream out, err;
  const int exit_code = RunCli({"run", kHover, "--out", dir_.string()}, out, err, &stop);
  EXPECT_EQ(exit_code, kExitCheckFailed);
  EXPECT_THAT(ReadFile(dir_ / "report.json"), HasSubstr("\"stop_reason\": \"interrupted\""));
}

}  // namespace
}  // namespace hilrig::host
