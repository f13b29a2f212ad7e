#include "host/plant/rotors.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace hilrig::host {
namespace {

TEST(RotorsTest, LagReaches63PercentAtTimeConstant) {
  RotorParams params;  // tau = 30 ms
  RotorState state;
  const std::array<double, 4> command = {2.0, 2.0, 2.0, 2.0};
  for (int i = 0; i < 30; ++i) state = StepRotors(params, state, command, 1e-3);
  for (double thrust : state.thrust_n) EXPECT_NEAR(thrust, 2.0 * (1.0 - std::exp(-1.0)), 1e-12);
}

TEST(RotorsTest, LagIsExactForAnyStepSize) {
  // Exact discretization: one 30 ms step lands where thirty 1 ms steps do.
  RotorParams params;
  const std::array<double, 4> command = {3.0, 1.0, 0.5, 2.0};
  RotorState fine;
  for (int i = 0; i < 30; ++i) fine = StepRotors(params, fine, command, 1e-3);
  const RotorState coarse = StepRotors(params, RotorState{}, command, 30e-3);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(coarse.thrust_n[i], fine.thrust_n[i], 1e-12);
}

TEST(RotorsTest, CommandsAreClampedToZeroAndMax) {
  RotorParams params;
  params.instantaneous = true;
  const std::array<double, 4> command = {-1.0, 5.0, 2.0, std::numeric_limits<double>::quiet_NaN()};
  const RotorState state = StepRotors(params, RotorState{}, command, 1e-3);
  EXPECT_EQ(state.thrust_n[0], 0.0);
  EXPECT_EQ(state.thrust_n[1], 4.0);
  EXPECT_EQ(state.thrust_n[2], 2.0);
  EXPECT_EQ(state.thrust_n[3], 0.0);
}

TEST(RotorsTest, InstantaneousRotorsFollowTheCommand) {
  RotorParams params;
  params.instantaneous = true;
  const RotorState state = StepRotors(params, RotorState{}, {1.0, 1.5, 2.0, 2.5}, 1e-3);
  EXPECT_EQ(state.thrust_n, (std::array<double, 4>{1.0, 1.5, 2.0, 2.5}));
}

TEST(RotorsTest, EachRotorTorqueHasTheLayoutSigns) {
  RotorParams params;  // L = 0.1, k = 0.016
  const double a = 0.1 / std::sqrt(2.0);
  // Rotor 0 front-right: lifts the right side (roll -) and the nose (pitch -), yaw -.
  // Rotor 1 back-left: roll +, pitch +, yaw -. Rotor 2 front-left: roll +, pitch -, yaw +.
  // Rotor 3 back-right: roll -, pitch +, yaw +.
  const Eigen::Vector3d expected_per_newton[4] = {
      {-a, -a, -0.016}, {+a, +a, -0.016}, {+a, -a, +0.016}, {-a, +a, +0.016}};
  for (int i = 0; i < 4; ++i) {
    RotorState state;
    state.thrust_n[i] = 1.0;
    const Eigen::Vector3d torque = RotorTorqueBody(params, state);
    EXPECT_LT((torque - expected_per_newton[i]).norm(), 1e-15) << "rotor " << i;
    // Cross-check against the definition r x (0, 0, T) + yaw reaction.
    const Eigen::Vector3d from_definition =
        RotorPositionBody(params, i).cross(Eigen::Vector3d(0, 0, 1)) +
        Eigen::Vector3d(0, 0, kRotorYawSign[i] * 0.016);
    EXPECT_LT((torque - from_definition).norm(), 1e-15) << "rotor " << i;
  }
}

TEST(RotorsTest, EqualThrustsGiveNoTorqueAndSumToCollective) {
  RotorParams params;
  RotorState state;
  state.thrust_n = {1.3, 1.3, 1.3, 1.3};
  EXPECT_LT(RotorTorqueBody(params, state).norm(), 1e-15);
  EXPECT_DOUBLE_EQ(CollectiveThrust(state), 5.2);
}

TEST(RotorsTest, AllocationMatrixMatchesTorqueAndCollective) {
  RotorParams params;
  RotorState state;
  state.thrust_n = {0.4, 1.1, 2.3, 0.7};
  const Eigen::Vector4d thrusts(0.4, 1.1, 2.3, 0.7);
  const Eigen::Vector4d mapped = RotorAllocationMatrix(params) * thrusts;
  EXPECT_NEAR(mapped(0), CollectiveThrust(state), 1e-15);
  EXPECT_LT((mapped.tail<3>() - RotorTorqueBody(params, state)).norm(), 1e-15);
}

}  // namespace
}  // namespace hilrig::host

#include "dut_fw/mixer.h"

namespace hilrig::host {
namespace {

// The plant and the DUT firmware each state the rotor layout; they must be the same airframe.
TEST(RotorLayoutTest, PlantAllocationMatchesTheFirmwareMixers) {
  const RotorParams params;
  const dut_fw::MixerGeometry<double> geometry{params.arm_length_m, params.torque_per_thrust_m,
                                               params.max_thrust_n};
  EXPECT_TRUE(
      RotorAllocationMatrix(params).isApprox(dut_fw::AllocationMatrix<double>(geometry), 1e-15));
}

}  // namespace
}  // namespace hilrig::host
