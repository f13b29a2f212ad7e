#include "host/scenario/reference_trajectory.h"

#include <gtest/gtest.h>

#include <numbers>

namespace hilrig::host {
namespace {

ReferenceSample AtOrigin() { return ReferenceSample{}; }

TEST(ReferenceTrajectoryTest, HoldsInitialBeforeFirstSetpoint) {
  const ReferenceTrajectory trajectory(AtOrigin(), {{1.0, {0, 0, 1}, 0, 2.0}});
  EXPECT_EQ(trajectory.Evaluate(0.5).position_m, Eigen::Vector3d::Zero());
}

TEST(ReferenceTrajectoryTest, MinimumJerkReachesTargetAtRest) {
  const ReferenceTrajectory trajectory(AtOrigin(), {{1.0, {0, 0, 1}, 0, 2.0}});
  const ReferenceSample end = trajectory.Evaluate(3.0);
  EXPECT_NEAR(end.position_m.z(), 1.0, 1e-12);
  EXPECT_NEAR(end.velocity_m_s.norm(), 0.0, 1e-12);
  EXPECT_NEAR(end.acceleration_m_s2.norm(), 0.0, 1e-12);
}

TEST(ReferenceTrajectoryTest, MidpointOfRestToRestMoveIsHalfwayAtPeakSpeed) {
  const ReferenceTrajectory trajectory(AtOrigin(), {{0.0, {0, 0, 1}, 0, 2.0}});
  const ReferenceSample middle = trajectory.Evaluate(1.0);
  EXPECT_NEAR(middle.position_m.z(), 0.5, 1e-12);
  EXPECT_NEAR(middle.velocity_m_s.z(), 15.0 / 8.0 * 1.0 / 2.0, 1e-12);  // 15/8 h/T
  EXPECT_NEAR(middle.acceleration_m_s2.z(), 0.0, 1e-12);
}

TEST(ReferenceTrajectoryTest, VelocityIsTheDerivativeOfPosition) {
  const ReferenceTrajectory trajectory(AtOrigin(), {{0.0, {1, -2, 3}, 0, 2.0}});
  const double h = 1e-6;
  for (double t : {0.3, 0.9, 1.7}) {
    const Eigen::Vector3d numeric =
        (trajectory.Evaluate(t + h).position_m - trajectory.Evaluate(t - h).position_m) / (2 * h);
    EXPECT_LT((numeric - trajectory.Evaluate(t).velocity_m_s).norm(), 1e-6) << "t = " << t;
  }
}

TEST(ReferenceTrajectoryTest, InterruptingSetpointKeepsPathContinuous) {
  const ReferenceTrajectory trajectory(AtOrigin(),
                                       {{0.0, {0, 0, 1}, 0, 2.0}, {1.0, {1, 0, 1}, 0, 2.0}});
  const ReferenceSample before = trajectory.Evaluate(1.0 - 1e-9);
  const ReferenceSample after = trajectory.Evaluate(1.0);
  EXPECT_LT((before.position_m - after.position_m).norm(), 1e-6);
  EXPECT_LT((before.velocity_m_s - after.velocity_m_s).norm(), 1e-6);
}

TEST(ReferenceTrajectoryTest, ZeroTransitionIsAStep) {
  const ReferenceTrajectory trajectory(AtOrigin(), {{1.0, {0.5, 0, 0}, 0, 0.0}});
  EXPECT_EQ(trajectory.Evaluate(1.0).position_m, Eigen::Vector3d(0.5, 0, 0));
}

TEST(ReferenceTrajectoryTest, YawTurnsTheShortWayRound) {
  const double start = 170.0 * std::numbers::pi / 180.0;
  const double target = -170.0 * std::numbers::pi / 180.0;
  ReferenceSample initial;
  initial.yaw_rad = start;
  const ReferenceTrajectory trajectory(initial, {{0.0, {0, 0, 0}, target, 2.0}});
  // Halfway along the 20 degree turn through 180 degrees.
  EXPECT_NEAR(std::abs(trajectory.Evaluate(1.0).yaw_rad), std::numbers::pi, 1e-9);
}

}  // namespace
}  // namespace hilrig::host
