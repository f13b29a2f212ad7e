// Setting a scenario's numbers by path: every kind of field a sweep axis can name, and every way a
// path or a value can be wrong, each refused with the part that is wrong and the spec unchanged.
#include "host/scenario/field_path.h"

#include <gmock/gmock.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include "host/scenario/scenario_loader.h"
#include "tests/support/bottle_scene.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

proto::Scenario BottleScene() {
  auto scenario = ParseScenario(kBottleSceneText, "bottle.textproto");
  EXPECT_TRUE(scenario.ok()) << scenario.error().message;
  return scenario.value();
}

TEST(FieldPathTest, SplitsNamesAndIndices) {
  auto parts = ParseFieldPath("timeline[12].grasp.force_n");
  ASSERT_TRUE(parts.ok()) << parts.error().message;
  ASSERT_EQ(parts.value().size(), 3u);
  EXPECT_EQ(parts.value()[0].name, "timeline");
  EXPECT_EQ(parts.value()[0].index, 12);
  EXPECT_EQ(parts.value()[1].index, -1);
  EXPECT_EQ(parts.value()[2].name, "force_n");
  for (const char* bad :
       {"", ".a", "a.", "a..b", "a[", "a[]", "a[-1]", "a[x]", "a[1]b", "a b", "a[9999999]"}) {
    auto parsed = ParseFieldPath(bad);
    ASSERT_FALSE(parsed.ok()) << bad;
    EXPECT_THAT(parsed.error().message, HasSubstr("field path \"" + std::string(bad) + "\""));
  }
}

TEST(FieldPathTest, SetsDoublesIntegersEnumsAndBools) {
  proto::Scenario scenario = BottleScene();
  ASSERT_TRUE(SetNumberAt(scenario, "vehicle.mass_kg", 0.6).ok());
  EXPECT_EQ(scenario.vehicle().mass_kg(), 0.6);
  ASSERT_TRUE(SetNumberAt(scenario, "object.mass_kg", 0.25).ok());
  EXPECT_EQ(scenario.object().mass_kg(), 0.25);
  EXPECT_EQ(scenario.object().fixture(), "water_bottle");
  ASSERT_TRUE(SetNumberAt(scenario, "timeline[1].grasp.force_n", 2.0).ok());
  EXPECT_EQ(scenario.timeline(1).grasp().force_n(), 2.0);
  // An unset message on the way is made, as the text format would make it.
  ASSERT_TRUE(SetNumberAt(scenario, "models.vio.latency_s", 0.05).ok());
  EXPECT_EQ(scenario.models().vio().latency_s(), 0.05);
  ASSERT_TRUE(SetNumberAt(scenario, "models.tactile.chip_noise", 0).ok());
  EXPECT_TRUE(scenario.models().tactile().has_chip_noise());
  EXPECT_FALSE(scenario.models().tactile().chip_noise());
  ASSERT_TRUE(SetNumberAt(scenario, "models.noise", 1).ok());
  EXPECT_EQ(scenario.models().noise(), proto::NOISE_OFF);
  ASSERT_TRUE(SetNumberAt(scenario, "simulation.plant_substeps", 4).ok());
  EXPECT_EQ(scenario.simulation().plant_substeps(), 4u);
  ASSERT_TRUE(SetNumberAt(scenario, "seed", 77).ok());
  EXPECT_EQ(scenario.seed(), 77u);
}

TEST(FieldPathTest, RefusesWhatIsNoNumberOfTheSpecAndChangesNothing) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"vehicle.weight_kg", "vehicle.weight_kg: Vehicle has no field weight_kg"},
      {"timeline.grasp.force_n", "timeline: a repeated field: name an element, timeline[N]"},
      {"vehicle[0].mass_kg", "vehicle: not a repeated field"},
      {"timeline[2].grasp.force_n", "timeline: no element 2 (the spec has 2)"},
      {"timeline[0].grasp.force_n", "timeline[0].grasp: this TimelineEntry holds setpoint"},
      {"vehicle.mass_kg.x", "a number, not a message"},
      {"object.fixture", "fixture is text, not a number"},
      {"vehicle.initial_position_m", "initial_position_m is a message (Vector3)"},
      {"models.vio", "vio is a message (Vio)"},
  };
  for (const auto& [path, why] : cases) {
    proto::Scenario scenario = BottleScene();
    const proto::Scenario before = scenario;
    auto set = SetNumberAt(scenario, path, 1.0);
    ASSERT_FALSE(set.ok()) << path;
    EXPECT_THAT(set.error().message, HasSubstr("\"" + path + "\": ")) << path;
    EXPECT_THAT(set.error().message, HasSubstr(why)) << path;
    EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(scenario, before)) << path;
    EXPECT_FALSE(CheckNumberPath(scenario, path).ok()) << path;
  }
}

TEST(FieldPathTest, SetsTheLargestSeedADoubleHoldsExactly) {
  proto::Scenario scenario = BottleScene();
  ASSERT_TRUE(SetNumberAt(scenario, "seed", 9007199254740992.0).ok());
  EXPECT_EQ(scenario.seed(), 9007199254740992u);
}

TEST(FieldPathTest, RefusesAValueTheFieldCannotHold) {
  const std::vector<std::tuple<std::string, double, std::string>> cases = {
      {"vehicle.mass_kg", std::nan(""), "not a finite number"},
      {"vehicle.mass_kg", INFINITY, "not a finite number"},
      {"simulation.plant_substeps", 2.5, "not a whole number in uint32's range"},
      {"simulation.plant_substeps", -1, "not a whole number in uint32's range"},
      {"models.tactile.chip_noise", 0.5, "a bool takes 0 or 1"},
      {"models.noise", 7, "not a number of Noise"},
      // 2^64 is no uint64 (its cast would run seed 0), and above 2^53 a double holds no whole
      // number for sure.
      {"seed", 18446744073709551616.0, "not a whole number in uint64's range"},
      {"seed", 9007199254740994.0, "that a double holds exactly"},
  };
  for (const auto& [path, value, why] : cases) {
    proto::Scenario scenario = BottleScene();
    const proto::Scenario before = scenario;
    auto set = SetNumberAt(scenario, path, value);
    ASSERT_FALSE(set.ok()) << path;
    EXPECT_THAT(set.error().message, HasSubstr(why)) << path;
    EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(scenario, before)) << path;
    EXPECT_TRUE(CheckNumberPath(scenario, path).ok()) << path;  // the path itself is fine
  }
}

}  // namespace
}  // namespace hilrig::host
