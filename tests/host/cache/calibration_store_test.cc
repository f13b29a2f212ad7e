#include "host/cache/calibration_store.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "fixtures/calibration/calibration_file.h"
#include "host/cache/setup_caches.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

proto::Scenario Spec(const std::string& name) {
  proto::Scenario spec;
  spec.set_name(name);
  spec.mutable_simulation()->set_duration_s(1);
  return spec;
}

// A calibration a DUT accepts (six nodes, finite gains), told apart from others by `gain`.
proto::Calibration SixSensors(double gain = 1.5) {
  proto::Calibration calibration;
  for (std::uint32_t node = 1; node <= 6; ++node) {
    proto::SensorCalibration* sensor = calibration.add_sensors();
    sensor->set_node_id(node);
    sensor->mutable_a()->set_x(gain * node);
    sensor->mutable_b()->set_z(-gain);
  }
  calibration.set_field_fidelity("tiles:8");
  return calibration;
}

// A tactile scene whose calibration takes milliseconds.
proto::Scenario Pads() {
  auto spec = ParseScenario(R"(name: "pads"
models { tactile { enabled: true field_fidelity: "tiles:4" } }
simulation { duration_s: 1 }
)",
                            "pads.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return spec.value();
}

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

TEST(CalibrationStoreTest, TheKeyChangesWithSpecSeedAndCode) {
  const std::string key = CalibrationCacheKey(Spec("a"), 1, "code-a");
  EXPECT_EQ(key.size(), 16u);
  EXPECT_EQ(key, CalibrationCacheKey(Spec("a"), 1, "code-a"));
  EXPECT_NE(key, CalibrationCacheKey(Spec("b"), 1, "code-a"));
  EXPECT_NE(key, CalibrationCacheKey(Spec("a"), 2, "code-a"));
  EXPECT_NE(key, CalibrationCacheKey(Spec("a"), 1, "code-b"));
  proto::Scenario longer = Spec("a");
  longer.mutable_simulation()->set_duration_s(2);
  EXPECT_NE(key, CalibrationCacheKey(longer, 1, "code-a"));
}

TEST(CalibrationStoreTest, StoreThenLoadAndMissesForOtherSeedsOrDamagedFiles) {
  const std::string dir = ::testing::TempDir() + "/calibration_store_test";
  std::filesystem::remove_all(dir);
  const FileCalibrationStore store(dir + "/nested", "code-a", nullptr);

  EXPECT_FALSE(store.Load(Spec("a"), 1).has_value());
  store.Store(Spec("a"), 1, SixSensors());
  const auto loaded = store.Load(Spec("a"), 1);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->SerializeAsString(), SixSensors().SerializeAsString());
  EXPECT_FALSE(store.Load(Spec("a"), 2).has_value());

  const std::string good = ReadFile(store.PathOf(Spec("a"), 1));
  std::ofstream(store.PathOf(Spec("a"), 1), std::ios::trunc) << "garbage";
  EXPECT_FALSE(store.Load(Spec("a"), 1).has_value()) << "foreign bytes";
  std::ofstream(store.PathOf(Spec("a"), 1), std::ios::trunc) << good.substr(0, 8);
  EXPECT_FALSE(store.Load(Spec("a"), 1).has_value()) << "the header and no calibration";
  std::filesystem::remove_all(dir);
}

TEST(CalibrationStoreTest, AStoreThatFailsIsSaid) {
  std::ostringstream notes;
  const FileCalibrationStore store(UncreatableFolder("calibration_store_").string(), "code-a",
                                   &notes);

  store.Store(Spec("pads"), 1, SixSensors());
  EXPECT_NE(notes.str().find("the pads calibration is not kept for later runs"), std::string::npos)
      << notes.str();
}

// The one path of `hilrig run` and `hilrig bench`: a miss calibrates and stores, a hit is what the
// store holds (a planted calibration comes back), and no store calibrates every time.
TEST(CalibrationStoreTest, CalibrateThroughStoreCalibratesOnceAndThenReads) {
  const std::string dir = ::testing::TempDir() + "/calibrate_through_store_test";
  std::filesystem::remove_all(dir);
  const FileCalibrationStore store(dir, "code-a", nullptr);
  const auto spec = ParseScenario(R"(name: "pads"
models { tactile { enabled: true field_fidelity: "tiles:4" } }
simulation { duration_s: 1 }
)",
                                  "pads.textproto");
  ASSERT_TRUE(spec.ok()) << spec.error().message;

  ScenarioConfig first = ResolveScenario(spec.value(), 1);
  ASSERT_TRUE(CalibrateThroughStore(spec.value(), first, &store).ok());
  ASSERT_TRUE(first.hall_sensors.calibration.has_value());
  EXPECT_EQ(first.hall_sensors.calibration->sensors_size(), 6);
  const auto stored = store.Load(spec.value(), 1);
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->SerializeAsString(), first.hall_sensors.calibration->SerializeAsString());

  store.Store(spec.value(), 1, SixSensors(7));
  ScenarioConfig second = ResolveScenario(spec.value(), 1);
  ASSERT_TRUE(CalibrateThroughStore(spec.value(), second, &store).ok());
  EXPECT_EQ(second.hall_sensors.calibration->SerializeAsString(),
            SixSensors(7).SerializeAsString());

  ScenarioConfig without_store = ResolveScenario(spec.value(), 1);
  ASSERT_TRUE(CalibrateThroughStore(spec.value(), without_store, nullptr).ok());
  EXPECT_EQ(without_store.hall_sensors.calibration->SerializeAsString(),
            first.hall_sensors.calibration->SerializeAsString());
  std::filesystem::remove_all(dir);
}

// A stop request ends a calibration with an error that says so in its code, which every layer
// keeps: callers decide on the code, not on the words.
TEST(CalibrationStoreTest, AStopRequestEndsTheCalibrationWithTheInterruptedCode) {
  const std::string dir = ::testing::TempDir() + "/calibration_interrupted_test";
  std::filesystem::remove_all(dir);
  const FileCalibrationStore store(dir, "code-a", nullptr);
  const proto::Scenario spec = Pads();
  const std::atomic<bool> stop_requested{true};

  ScenarioConfig config = ResolveScenario(spec, 1);
  const auto calibrated = LoadTactileCalibration(config, &stop_requested);
  ASSERT_FALSE(calibrated.ok());
  EXPECT_EQ(calibrated.error().code, rig::ErrorCode::kInterrupted);
  EXPECT_EQ(calibrated.error().message, "interrupted");

  ScenarioConfig through_store = ResolveScenario(spec, 1);
  const auto set_up = SetUpTactile(spec, through_store, nullptr, &store, &stop_requested);
  ASSERT_FALSE(set_up.ok());
  EXPECT_EQ(set_up.error().code, rig::ErrorCode::kInterrupted);
  EXPECT_EQ(set_up.error().message, "tactile calibration: interrupted");
  EXPECT_FALSE(store.Load(spec, 1).has_value());
  std::filesystem::remove_all(dir);
}

// Protobuf parses many cuts of a message as a shorter valid message (fewer sensors): each one
// used to reach the DUT, which read past its six nodes. Every cut is now a miss, and said.
TEST(CalibrationStoreTest, AnEntryCutAtAnyLengthIsAMissAndIsSaid) {
  const fs::path dir = FreshTestDir("calibration_store_");
  std::ostringstream notes;
  const FileCalibrationStore store(dir.string(), "code-a", &notes);
  store.Store(Spec("a"), 1, SixSensors());
  const std::string path = store.PathOf(Spec("a"), 1);
  const std::string whole = ReadFile(path);
  ASSERT_TRUE(store.Load(Spec("a"), 1).has_value());

  for (std::size_t length = 0; length < whole.size(); ++length) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << whole.substr(0, length);
    EXPECT_FALSE(store.Load(Spec("a"), 1).has_value()) << "cut to " << length << " bytes";
  }
  EXPECT_EQ(Count(notes.str(), path), whole.size()) << notes.str();
  EXPECT_EQ(Count(notes.str(), "made again"), whole.size());
}

// An entry whose bytes are whole but whose calibration a DUT would refuse (re-encoded with NaN
// gains, or fewer nodes) is a miss: the scene is calibrated again and the entry replaced.
TEST(CalibrationStoreTest, AnEntryADutWouldRefuseIsAMissAndIsMadeAgain) {
  const fs::path dir = FreshTestDir("calibration_store_");
  std::ostringstream notes;
  const FileCalibrationStore store(dir.string(), "code-a", &notes);
  const proto::Scenario spec = Pads();
  proto::Calibration nan_gain = SixSensors();
  nan_gain.mutable_sensors(2)->mutable_a()->set_y(std::numeric_limits<double>::quiet_NaN());
  proto::Calibration two_nodes = SixSensors();
  two_nodes.mutable_sensors()->DeleteSubrange(2, 4);

  for (const proto::Calibration& refused : {nan_gain, two_nodes}) {
    store.Store(spec, 1, refused);
    EXPECT_FALSE(store.Load(spec, 1).has_value());
    ScenarioConfig config = ResolveScenario(spec, 1);
    ASSERT_TRUE(CalibrateThroughStore(spec, config, &store).ok());
    ASSERT_TRUE(config.hall_sensors.calibration.has_value());
    EXPECT_TRUE(fixtures::ValidateCalibration(*config.hall_sensors.calibration, "made").ok());
    const auto stored = store.Load(spec, 1);
    ASSERT_TRUE(stored.has_value()) << "the entry made again replaced the refused one";
    EXPECT_EQ(stored->SerializeAsString(), config.hall_sensors.calibration->SerializeAsString());
  }
  EXPECT_NE(notes.str().find("node 3 has a non-finite gain"), std::string::npos) << notes.str();
  EXPECT_NE(notes.str().find("needs the six tactile nodes, has 2"), std::string::npos);
}

// A folder or a FIFO where an entry should be is a miss (it used to throw ios_failure out of the
// run, or block on the FIFO); a store over the folder fails and is said, and the run goes on.
TEST(CalibrationStoreTest, AFolderOrAFifoAtTheEntryPathIsAMissAndTheRunGoesOn) {
  const fs::path dir = FreshTestDir("calibration_store_");
  std::ostringstream notes;
  const FileCalibrationStore store(dir.string(), "code-a", &notes);
  const proto::Scenario spec = Pads();
  fs::create_directories(store.PathOf(spec, 1));
  ASSERT_EQ(::mkfifo(store.PathOf(spec, 2).c_str(), 0600), 0);

  for (std::uint64_t seed : {1, 2}) {
    EXPECT_FALSE(store.Load(spec, seed).has_value());
    ScenarioConfig config = ResolveScenario(spec, seed);
    ASSERT_TRUE(CalibrateThroughStore(spec, config, &store).ok());
    EXPECT_EQ(config.hall_sensors.calibration->sensors_size(), 6);
  }
  EXPECT_NE(notes.str().find("a folder, not a regular file"), std::string::npos) << notes.str();
  EXPECT_NE(notes.str().find("a FIFO, not a regular file"), std::string::npos);
  EXPECT_NE(notes.str().find("the pads calibration is not kept for later runs: cannot write " +
                             store.PathOf(spec, 1)),
            std::string::npos);
  EXPECT_TRUE(fs::is_directory(store.PathOf(spec, 1)));
  EXPECT_TRUE(store.Load(spec, 2).has_value()) << "the FIFO was replaced by the entry";
}

}  // namespace
}  // namespace hilrig::host
