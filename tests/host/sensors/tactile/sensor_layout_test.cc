#include "host/sensors/tactile/sensor_layout.h"

#include <gtest/gtest.h>

#include "host/sensors/earth_field.h"

namespace hilrig::host {
namespace {

TEST(SensorLayoutTest, SixDistinctUnitNormalsPointToTheFrameCentre) {
  const auto layout = DefaultTactileLayout();
  for (int i = 0; i < kTactileSensorCount; ++i) {
    const Eigen::Vector3d n = ContactNormalBody(layout[i]);
    EXPECT_NEAR(n.norm(), 1.0, 1e-12) << i;
    const Eigen::Vector3d to_centre = -layout[i].position_body_m.normalized();
    EXPECT_NEAR(n.dot(to_centre), 1.0, 1e-12) << i;
    for (int j = 0; j < i; ++j) {
      EXPECT_GT((n - ContactNormalBody(layout[j])).norm(), 0.5) << i << " " << j;
    }
  }
}

TEST(SensorLayoutTest, OppositePadsFaceEachOther) {
  const auto layout = DefaultTactileLayout();
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT((ContactNormalBody(layout[i]) + ContactNormalBody(layout[i + 3])).norm(), 1e-12);
  }
}

TEST(SensorLayoutTest, PadsSitOnTheRingInTheBodyPlane) {
  const auto layout = DefaultTactileLayout();
  for (const TactileSensorParams& s : layout) {
    EXPECT_NEAR(s.position_body_m.head<2>().norm(), 0.050, 1e-12);
    EXPECT_NEAR(s.position_body_m.z(), 0.0, 1e-12);
    // Film at -z of the chip lies inside the ring: 10 mm towards the centre.
    const Eigen::Vector3d film_body =
        s.position_body_m + s.mounting_body_from_sensor * FilmPose{}.centre_m;
    EXPECT_NEAR(film_body.head<2>().norm(), 0.040, 1e-12);
  }
}

TEST(SensorLayoutTest, NodeIdsAreOneToSixAndSevenForTheReference) {
  const auto layout = DefaultTactileLayout();
  for (int i = 0; i < kTactileSensorCount; ++i) {
    EXPECT_EQ(layout[i].node_id, i + 1);
    EXPECT_TRUE(layout[i].film_present);
  }
  const TactileSensorParams reference = DefaultReferenceSensor();
  EXPECT_EQ(reference.node_id, 7);
  EXPECT_FALSE(reference.film_present);
  EXPECT_TRUE(reference.earth_field_enabled);
}

TEST(SensorLayoutTest, RotationSensorFromReferenceIsAProperRotation) {
  const auto layout = DefaultTactileLayout();
  const TactileSensorParams reference = DefaultReferenceSensor();
  for (const TactileSensorParams& s : layout) {
    const Eigen::Matrix3d r = RotationSensorFromReference(s, reference);
    EXPECT_TRUE((r.transpose() * r).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
    EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  }
}

TEST(SensorLayoutTest, RotationSensorFromReferenceCarriesTheEarthFieldAtAnyAttitude) {
  const auto layout = DefaultTactileLayout();
  TactileSensorParams reference = DefaultReferenceSensor();
  // A tilted reference mounting, so the test does not pass by R_BSref = I alone.
  reference.mounting_body_from_sensor =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -1, 2).normalized());
  const Eigen::Vector3d earth_world_t(0.0, 2.4e-5, -4.16e-5);
  for (const double angle : {0.0, 0.4, 2.0}) {
    const Eigen::Quaterniond attitude(
        Eigen::AngleAxisd(angle, Eigen::Vector3d(3, 1, -2).normalized()));
    const Eigen::Vector3d b_ref =
        EarthFieldInSensorFrame(attitude, reference.mounting_body_from_sensor, earth_world_t);
    for (const TactileSensorParams& s : layout) {
      const Eigen::Vector3d b_i =
          EarthFieldInSensorFrame(attitude, s.mounting_body_from_sensor, earth_world_t);
      EXPECT_LT((RotationSensorFromReference(s, reference) * b_ref - b_i).norm(), 1e-18);
    }
  }
}

TEST(SensorLayoutTest, LayoutKeepsTheBaseSensorSettings) {
  TactileSensorParams base;
  base.chip.setting.gain_sel = 5;
  base.silicone.youngs_modulus_pa = 100e3;
  const auto layout = DefaultTactileLayout(base);
  for (const TactileSensorParams& s : layout) {
    EXPECT_EQ(s.chip.setting.gain_sel, 5);
    EXPECT_EQ(s.silicone.youngs_modulus_pa, 100e3);
  }
}

}  // namespace
}  // namespace hilrig::host
