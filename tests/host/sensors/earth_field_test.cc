#include "host/sensors/earth_field.h"

#include <gtest/gtest.h>

#include <numbers>

namespace hilrig::host {
namespace {

const Eigen::Quaterniond kIdentity = Eigen::Quaterniond::Identity();

TEST(EarthFieldTest, LevelBodyAlignedSensorReadsTheWorldField) {
  const EarthField earth;
  EXPECT_TRUE(EarthFieldInSensorFrame(kIdentity, kIdentity, earth.field_world_t)
                  .isApprox(earth.field_world_t, 1e-15));
}

TEST(EarthFieldTest, YawingTheVehicleLeftTurnsNorthToTheSensorsRight) {
  // Facing north after a 90 degree left yaw from east: north is straight ahead (+x body).
  const Eigen::Quaterniond yaw_left(
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d reading =
      EarthFieldInSensorFrame(yaw_left, kIdentity, Eigen::Vector3d(0, 24e-6, -41.6e-6));
  EXPECT_NEAR(reading.x(), 24e-6, 1e-15);
  EXPECT_NEAR(reading.y(), 0, 1e-15);
  EXPECT_NEAR(reading.z(), -41.6e-6, 1e-15);
}

TEST(EarthFieldTest, MountingAndAttitudeCompose) {
  const Eigen::Quaterniond attitude(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Quaterniond mounting(Eigen::AngleAxisd(-1.1, Eigen::Vector3d(0, 1, 1).normalized()));
  const Eigen::Vector3d field(1e-5, 2e-5, -4e-5);
  const Eigen::Vector3d expected =
      mounting.toRotationMatrix().transpose() * attitude.toRotationMatrix().transpose() * field;
  EXPECT_TRUE(EarthFieldInSensorFrame(attitude, mounting, field).isApprox(expected, 1e-12));
}

}  // namespace
}  // namespace hilrig::host
