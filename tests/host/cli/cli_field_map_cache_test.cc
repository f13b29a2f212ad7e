// `hilrig run` keeps tabulated field maps and calibrations beside its reference cache, so that only
// the first run of a build makes them. The maps are shared within a process, so this runs the
// hilrig executable once per run, as a user does.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

// An entry is written to a new file renamed into place, so a rewrite changes the inode; a read
// only touches the file (its time marks it used), so the inode stays.
ino_t InodeOf(const fs::path& path) {
  struct stat status {};
  EXPECT_EQ(::stat(path.c_str(), &status), 0) << path;
  return status.st_ino;
}

class CliFieldMapCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshTestDir("hilrig_cli_field_map_cache_");
    std::ofstream(dir_ / "pads.textproto") << R"(name: "pads"
seed: 5
vehicle { initial_position_m { z: 1 } }
models { tactile { enabled: true field_fidelity: "map:2" zeroing_s: 0.2 } }
simulation { duration_s: 0.5 }
envelopes { name: "alt" signal: ALTITUDE_M upper: 2 }
)";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs the scene into out/<name>; true when hilrig exited 0.
  bool Run(const std::string& name) {
    const std::string command =
        ::hilrig::test_support::BinDir() + "/hilrig run " + (dir_ / "pads.textproto").string() +
        " --no-reference --out " + (dir_ / "out" / name).string() + " --reference-cache " +
        (dir_ / "cache").string() + " > " + (dir_ / (name + ".log")).string() + " 2>&1";
    return std::system(command.c_str()) == 0;
  }
  std::vector<fs::path> Cached(const std::string& folder) const {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir_ / "cache" / folder)) {
      files.push_back(entry.path());
    }
    return files;
  }
  std::vector<fs::path> CachedMaps() const { return Cached("field_maps"); }
  std::string Trace(const std::string& name) const {
    return ReadFile(dir_ / "out" / name / "trace.csv");
  }

  fs::path dir_;
};

TEST_F(CliFieldMapCacheTest, TheFirstRunKeepsTheMapAndLaterRunsReadItToTheSameTrace) {
  ASSERT_TRUE(Run("first")) << ReadFile(dir_ / "first.log");
  ASSERT_EQ(CachedMaps().size(), 1u);
  const fs::path map = CachedMaps().front();
  EXPECT_EQ(map.extension(), ".map");
  const ino_t written = InodeOf(map);

  ASSERT_TRUE(Run("second")) << ReadFile(dir_ / "second.log");
  EXPECT_EQ(InodeOf(map), written) << "read, not tabulated and written again";
  EXPECT_EQ(Trace("second"), Trace("first"));
  EXPECT_GT(Trace("first").size(), 100u);
}

TEST_F(CliFieldMapCacheTest, ADamagedMapIsTabulatedAgainToTheSameTrace) {
  ASSERT_TRUE(Run("first")) << ReadFile(dir_ / "first.log");
  ASSERT_EQ(CachedMaps().size(), 1u);
  const fs::path map = CachedMaps().front();
  const std::string good = ReadFile(map);
  std::ofstream(map, std::ios::trunc) << good.substr(0, good.size() / 2);

  ASSERT_TRUE(Run("second")) << ReadFile(dir_ / "second.log");
  EXPECT_EQ(Trace("second"), Trace("first"));
  EXPECT_EQ(ReadFile(map), good) << "the tabulated map replaced the damaged one";
}

TEST_F(CliFieldMapCacheTest, TheCalibrationIsKeptAndADamagedOneIsMadeAgain) {
  ASSERT_TRUE(Run("first")) << ReadFile(dir_ / "first.log");
  ASSERT_EQ(Cached("calibrations").size(), 1u);
  const fs::path calibration = Cached("calibrations").front();
  const ino_t written = InodeOf(calibration);
  ASSERT_TRUE(Run("second")) << ReadFile(dir_ / "second.log");
  EXPECT_EQ(InodeOf(calibration), written) << "read, not made and written again";
  EXPECT_EQ(Trace("second"), Trace("first"));

  const std::string good = ReadFile(calibration);
  std::ofstream(calibration, std::ios::trunc) << "garbage";
  ASSERT_TRUE(Run("third")) << ReadFile(dir_ / "third.log");
  EXPECT_EQ(Trace("third"), Trace("first"));
  EXPECT_EQ(ReadFile(calibration), good) << "the calibration made again replaced the damaged one";
}

// A folder where the calibration and the map entries should be: both are misses (the run used to
// abort on an uncaught ios_failure), the stores over them fail and are said, and the run gives the
// same trace.
TEST_F(CliFieldMapCacheTest, FoldersAtTheEntryPathsAreMissesAndTheRunGoesOn) {
  ASSERT_TRUE(Run("first")) << ReadFile(dir_ / "first.log");
  const fs::path calibration = Cached("calibrations").at(0);
  const fs::path map = CachedMaps().at(0);
  for (const fs::path& entry : {calibration, map}) {
    fs::remove(entry);
    fs::create_directory(entry);
  }

  ASSERT_TRUE(Run("second")) << ReadFile(dir_ / "second.log");
  EXPECT_EQ(Trace("second"), Trace("first"));
  const std::string log = ReadFile(dir_ / "second.log");
  for (const fs::path& entry : {calibration, map}) {
    EXPECT_NE(log.find("cannot read " + entry.string() + ": a folder"), std::string::npos) << log;
    EXPECT_NE(log.find("cannot write " + entry.string()), std::string::npos) << log;
    EXPECT_TRUE(fs::is_directory(entry));
  }
}

}  // namespace
}  // namespace hilrig::host
