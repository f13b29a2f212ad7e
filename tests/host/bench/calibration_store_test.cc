#include "host/bench/calibration_store.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

proto::Scenario Spec(const std::string& name) {
  proto::Scenario spec;
  spec.set_name(name);
  spec.mutable_simulation()->set_duration_s(1);
  return spec;
}

proto::Calibration TwoSensors() {
  proto::Calibration calibration;
  calibration.add_sensors()->set_node_id(1);
  calibration.add_sensors()->set_node_id(2);
  calibration.set_field_fidelity("tiles:8");
  return calibration;
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
  store.Store(Spec("a"), 1, TwoSensors());
  const auto loaded = store.Load(Spec("a"), 1);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->SerializeAsString(), TwoSensors().SerializeAsString());
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

  store.Store(Spec("pads"), 1, TwoSensors());
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

  store.Store(spec.value(), 1, TwoSensors());
  ScenarioConfig second = ResolveScenario(spec.value(), 1);
  ASSERT_TRUE(CalibrateThroughStore(spec.value(), second, &store).ok());
  EXPECT_EQ(second.hall_sensors.calibration->SerializeAsString(), TwoSensors().SerializeAsString());

  ScenarioConfig without_store = ResolveScenario(spec.value(), 1);
  ASSERT_TRUE(CalibrateThroughStore(spec.value(), without_store, nullptr).ok());
  EXPECT_EQ(without_store.hall_sensors.calibration->SerializeAsString(),
            first.hall_sensors.calibration->SerializeAsString());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hilrig::host
