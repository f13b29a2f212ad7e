// `hilrig replay` end to end: a run recorded with its DUT in a dut_emu process and replayed on the
// DUT in this process gives no difference; a changed gain is found at the output it reaches
// first; logs that are missing, cut short or not logs at all are told apart.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "host/cli/cli.h"
#include "tests/support/hilrig_process.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kBalloon =
    ::hilrig::test_support::SourceDir() + "/scenarios/balloon_grasp.textproto";

class CliReplayTest : public ::testing::Test {
 protected:
  // One recording for the suite: 3 s of balloon_grasp (the grasp starts at 1.5 s) with the DUT
  // in its own process.
  static void SetUpTestSuite() {
    // ctest runs each test in a process of its own, in parallel: a folder per process.
    dir_ = new fs::path(fs::path(::testing::TempDir()) /
                        ("hilrig_cli_replay_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const ProcessResult recorded =
        RunHilrig("run " + kBalloon + " --no-reference --duration-s 3 --dut process --out " +
                      (*dir_ / "run").string() + " >" + (*dir_ / "run.out").string(),
                  *dir_ / "run.err");
    // The scene's held envelope opens later: the first 3 s may fail a check; the run is whole.
    ASSERT_LE(recorded.exit_code, kExitCheckFailed) << recorded.err;
    ASSERT_TRUE(fs::is_regular_file(*dir_ / "run" / "run.mcap"));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }

  struct Replayed {
    int exit_code;
    std::string out;
    std::string err;
  };
  Replayed Replay(const std::string& arguments) {
    const fs::path out = *dir_ / "replay.out";
    const ProcessResult result =
        RunHilrig("replay " + arguments + " >" + out.string(), *dir_ / "replay.err");
    return {result.exit_code, ReadFile(out), result.err};
  }
  static fs::path* dir_;
};

fs::path* CliReplayTest::dir_ = nullptr;

TEST_F(CliReplayTest, AProcessRecordingReplaysOnTheInProcessDutWithoutDifference) {
  const Replayed replayed = Replay((*dir_ / "run").string());
  EXPECT_EQ(replayed.exit_code, kExitPass) << replayed.out << replayed.err;
  EXPECT_THAT(replayed.out, HasSubstr("replayed 3000 steps"));
  EXPECT_THAT(replayed.out, HasSubstr("3000 commands compared"));
  EXPECT_THAT(replayed.out, HasSubstr("SAME: no output parted by more than 1e-09"));
}

TEST_F(CliReplayTest, AChangedDampingPartsAtTheServoFirstAndSaysWhen) {
  const fs::path out = *dir_ / "damping";
  const Replayed replayed = Replay((*dir_ / "run" / "run.mcap").string() +
                                   " --set grasp_controller.damping=260 --out " + out.string());
  EXPECT_EQ(replayed.exit_code, kExitCheckFailed) << replayed.out << replayed.err;
  // The grasp controller acts from the grasp command at 1.5 s on; the servo is its output.
  EXPECT_THAT(replayed.out, HasSubstr("DIFFERS: servo_angle_rad parts first, at tick 1688"));
  const std::string json = ReadFile(out / "replay.json");
  EXPECT_THAT(json, HasSubstr("\"first_parted\": \"servo_angle_rad\""));
  EXPECT_THAT(json, HasSubstr("\"verdict\": \"REPLAY_DIFFERS\""));
}

TEST_F(CliReplayTest, TheCalibrationComesFromTheCacheNamedAsForRun) {
  const fs::path cache = *dir_ / "cache";
  const Replayed replayed =
      Replay((*dir_ / "run").string() + " --reference-cache " + cache.string());
  EXPECT_EQ(replayed.exit_code, kExitPass) << replayed.out << replayed.err;
  EXPECT_TRUE(fs::is_directory(cache / "calibrations"));
}

TEST_F(CliReplayTest, ALogCutShortReplaysItsCompleteChunks) {
  const fs::path cut = *dir_ / "cut.mcap";
  const std::string bytes = ReadFile(*dir_ / "run" / "run.mcap");
  ASSERT_GT(bytes.size(), 1u << 20);  // more than one chunk
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 4096);
  const Replayed replayed = Replay(cut.string());
  EXPECT_EQ(replayed.exit_code, kExitPass) << replayed.out << replayed.err;
  EXPECT_THAT(replayed.out, HasSubstr("the log was cut short"));
}

TEST_F(CliReplayTest, WhatIsNotARecordedRunIsBadInput) {
  const fs::path empty = *dir_ / "empty";
  fs::create_directories(empty);
  Replayed replayed = Replay(empty.string());
  EXPECT_EQ(replayed.exit_code, kExitBadInput);
  EXPECT_THAT(replayed.err, HasSubstr("run.mcap"));

  std::ofstream(*dir_ / "junk.mcap") << "not an mcap file at all";
  replayed = Replay((*dir_ / "junk.mcap").string());
  EXPECT_EQ(replayed.exit_code, kExitBadInput);
  EXPECT_THAT(replayed.err, HasSubstr("junk.mcap"));

  replayed = Replay((*dir_ / "run").string() + " --set grasp_controller.no_such_gain=1");
  EXPECT_EQ(replayed.exit_code, kExitBadInput);
  EXPECT_THAT(replayed.err, HasSubstr("no_such_gain"));

  replayed = Replay((*dir_ / "run").string() + " --tolerance -1");
  EXPECT_EQ(replayed.exit_code, kExitBadInput);
  EXPECT_THAT(replayed.err, HasSubstr("--tolerance"));
}

}  // namespace
}  // namespace hilrig::host
