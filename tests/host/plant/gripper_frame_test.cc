#include "host/plant/gripper_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "host/sensors/tactile/sensor_layout.h"

namespace hilrig::host {
namespace {

TEST(GripperFrameTest, PadRadiusShrinksLinearlyWithTheAngle) {
  const GripperFrameParams frame;
  EXPECT_DOUBLE_EQ(PadSurfaceRadius(frame, 0.0), 0.055);
  EXPECT_DOUBLE_EQ(PadSurfaceRadius(frame, 1.0), 0.030);
  EXPECT_NEAR(PadSurfaceRadius(frame, 1.6), 0.015, 1e-15);
}

TEST(GripperFrameTest, PadRadiusNeverGoesBelowZero) {
  const GripperFrameParams frame;
  EXPECT_EQ(PadSurfaceRadius(frame, 10.0), 0.0);
}

TEST(GripperFrameTest, NaNAngleReadsAsOpen) {
  const GripperFrameParams frame;
  EXPECT_EQ(PadSurfaceRadius(frame, std::numeric_limits<double>::quiet_NaN()), 0.055);
}

TEST(GripperFrameTest, OutwardVectorsAreEvery60DegreesFrom30) {
  const GripperFrameParams frame;
  for (int i = 0; i < kGripperPadCount; ++i) {
    const double azimuth = (30.0 + 60.0 * i) * std::numbers::pi / 180.0;
    const Eigen::Vector3d outward = PadOutwardBody(frame, i);
    EXPECT_NEAR(outward.x(), std::cos(azimuth), 1e-15) << i;
    EXPECT_NEAR(outward.y(), std::sin(azimuth), 1e-15) << i;
    EXPECT_EQ(outward.z(), 0.0);
  }
}

TEST(GripperFrameTest, OutwardIsTheSensorLayoutsZAxis) {
  // The pads translate without turning, so the sensor's z_S (radially outward) is the frame's
  // outward vector and the contact normal is its negative at every angle.
  const GripperFrameParams frame;
  const auto layout = DefaultTactileLayout();
  for (int i = 0; i < kGripperPadCount; ++i) {
    const Eigen::Vector3d z_s = layout[i].mounting_body_from_sensor * Eigen::Vector3d::UnitZ();
    EXPECT_LT((PadOutwardBody(frame, i) - z_s).norm(), 1e-12) << i;
    EXPECT_LT((ContactNormalBody(layout[i]) + PadOutwardBody(frame, i)).norm(), 1e-12) << i;
  }
}

TEST(GripperFrameTest, ChipSitsTheStandoffBehindTheSurface) {
  GripperFrameParams frame;
  frame.height_m = 0.02;
  const Eigen::Vector3d surface = PadSurfaceBody(frame, 1, 0.8);  // pad 1 at 90 deg
  const Eigen::Vector3d chip = ChipPositionBody(frame, 1, 0.8);
  EXPECT_NEAR(surface.x(), 0.0, 1e-15);
  EXPECT_NEAR(surface.y(), 0.055 - 0.025 * 0.8, 1e-15);
  EXPECT_EQ(surface.z(), 0.02);
  EXPECT_NEAR(chip.y(), 0.055 - 0.025 * 0.8 + 0.010, 1e-15);
  EXPECT_EQ(chip.z(), 0.02);
}

TEST(GripperFrameTest, AngleForPadRadiusInvertsTheRadius) {
  const GripperFrameParams frame;
  EXPECT_NEAR(AngleForPadRadius(frame, 0.015), 1.6, 1e-12);
  EXPECT_NEAR(AngleForPadRadius(frame, PadSurfaceRadius(frame, 0.37)), 0.37, 1e-12);
}

TEST(GripperFrameTest, AngleForBadRadiusIsZero) {
  const GripperFrameParams frame;
  EXPECT_EQ(AngleForPadRadius(frame, std::numeric_limits<double>::quiet_NaN()), 0.0);
  GripperFrameParams stuck;
  stuck.closing_m_per_rad = 0.0;
  EXPECT_EQ(AngleForPadRadius(stuck, 0.02), 0.0);
}

TEST(GripperFrameTest, ValidateNamesTheField) {
  EXPECT_TRUE(ValidateGripperFrame(GripperFrameParams{}).ok());
  GripperFrameParams frame;
  frame.closing_m_per_rad = -0.01;
  const auto result = ValidateGripperFrame(frame);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("closing_m_per_rad"), std::string::npos);
}

}  // namespace
}  // namespace hilrig::host
