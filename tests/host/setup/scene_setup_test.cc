// The scene setup that may take long: the film field a scene's fidelity asks for, kept when the
// caller shares one, none without pads, and an unknown level named in the error.
#include "host/setup/scene_setup.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "host/sensors/tactile/dipole_film_field.h"
#include "host/sensors/tactile/film_field_factory.h"

namespace hilrig::host {
namespace {

ScenarioConfig TactileConfig(const std::string& field_fidelity) {
  proto::Scenario spec;
  spec.set_name("film");
  spec.mutable_simulation()->set_duration_s(1);
  spec.mutable_models()->mutable_tactile()->set_enabled(true);
  spec.mutable_models()->mutable_tactile()->set_field_fidelity(field_fidelity);
  return ResolveScenario(spec, std::nullopt);
}

TEST(BuildFilmFieldTest, BuildsTheScenesFieldLevel) {
  ScenarioConfig config = TactileConfig("tiles:4");

  ASSERT_TRUE(BuildFilmField(config).ok());

  ASSERT_NE(config.hall_sensors.film_field, nullptr);
  FilmPose pose;
  pose.centre_m = Eigen::Vector3d(0.0004, -0.0002, -0.0095);
  const Eigen::Vector3d expected_t = MakeFilmField("tiles:4").value()->FieldAtChip(pose);
  EXPECT_EQ(config.hall_sensors.film_field->FieldAtChip(pose), expected_t);
}

TEST(BuildFilmFieldTest, ConfigsOfOneOwnerShareTheirLevelsModel) {
  FilmFieldModels models;
  ScenarioConfig first = TactileConfig("tiles:4");
  ScenarioConfig second = TactileConfig("tiles:4");
  ScenarioConfig alone = TactileConfig("tiles:4");

  ASSERT_TRUE(BuildFilmField(first, &models).ok());
  ASSERT_TRUE(BuildFilmField(second, &models).ok());
  ASSERT_TRUE(BuildFilmField(alone).ok());

  EXPECT_EQ(first.hall_sensors.film_field, second.hall_sensors.film_field);
  EXPECT_NE(alone.hall_sensors.film_field, first.hall_sensors.film_field);
}

TEST(BuildFilmFieldTest, KeepsAFieldTheCallerShares) {
  ScenarioConfig config = TactileConfig("tiles:4");
  const auto shared = std::make_shared<const DipoleFilmField>(
      std::vector<PointDipole>{{Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1e-3)}});
  config.hall_sensors.film_field = shared;

  ASSERT_TRUE(BuildFilmField(config).ok());

  EXPECT_EQ(config.hall_sensors.film_field, shared);
}

TEST(BuildFilmFieldTest, BuildsNothingWithoutThePads) {
  proto::Scenario spec;
  spec.set_name("no pads");
  spec.mutable_simulation()->set_duration_s(1);
  ScenarioConfig config = ResolveScenario(spec, std::nullopt);

  ASSERT_TRUE(BuildFilmField(config).ok());

  EXPECT_EQ(config.hall_sensors.film_field, nullptr);
}

TEST(BuildFilmFieldTest, UnknownLevelIsAnErrorNamingIt) {
  ScenarioConfig config = TactileConfig("tiles:4");
  config.hall_sensors.field_fidelity = "voxels:9";

  const auto built = BuildFilmField(config);

  ASSERT_FALSE(built.ok());
  EXPECT_NE(built.error().message.find("voxels:9"), std::string::npos);
  EXPECT_EQ(config.hall_sensors.film_field, nullptr);
}

}  // namespace
}  // namespace hilrig::host
