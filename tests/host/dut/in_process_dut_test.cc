#include "host/dut/in_process_dut.h"

#include <gtest/gtest.h>

#include <limits>

#include "host/dut/firmware_config.h"
#include "rig/emulated_bus.h"
#include "rig/tactile_protocol.h"

namespace hilrig::host {
namespace {

constexpr double kControlPeriodS = 1e-3;

// Regulate the grasp at 0.6 N from a 0.5 rad reference angle.
SetpointMessage GraspSetpoint() {
  SetpointMessage setpoint;
  setpoint.grasp_regulate = true;
  setpoint.grasp_force_n = 0.6;
  setpoint.grasp_reference_angle_rad = 0.5;
  return setpoint;
}

class InProcessDutTest : public ::testing::Test {
 protected:
  InProcessDutTest()
      : node_(bus_.Connect("node")),
        dut_(DutFirmware{FirmwareParamsFor(vehicle_), std::nullopt, {}, true}, bus_.Connect("dut"),
             kControlPeriodS) {}

  // Feeds a level, still vehicle at 1 m for `ticks` control periods with a hover setpoint.
  ActuatorMessage HoverFor(int ticks) {
    dut_.Send(VioMessage{{0, 0}, 0, Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity()});
    dut_.Send(SetpointMessage{
        {0, 0}, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0});
    ActuatorMessage command;
    for (int i = 1; i <= ticks; ++i) {
      const std::int64_t now_ns = i * 1'000'000;
      dut_.Send(ImuMessage{{static_cast<std::uint64_t>(i), now_ns},
                           Eigen::Vector3d::Zero(),
                           Eigen::Vector3d(0, 0, vehicle_.gravity_m_s2)});
      command = dut_.Step(static_cast<std::uint64_t>(i), now_ns).value();
    }
    return command;
  }

  QuadrotorParams vehicle_;
  rig::EmulatedBus bus_;
  std::unique_ptr<rig::CanBus> node_;
  InProcessDut dut_;
};

TEST_F(InProcessDutTest, StaysDisarmedUntilItHasAPose) {
  const ActuatorMessage command = dut_.Step(0, 0).value();
  EXPECT_FALSE(command.armed);
  for (double thrust_n : command.rotor_thrust_n) EXPECT_EQ(thrust_n, 0.0);
}

TEST_F(InProcessDutTest, HoldsHoverWithAQuarterOfTheWeightPerRotor) {
  const ActuatorMessage command = HoverFor(200);
  ASSERT_TRUE(command.armed);
  const double quarter_weight_n = vehicle_.body.mass_kg * vehicle_.gravity_m_s2 / 4;
  for (double thrust_n : command.rotor_thrust_n) EXPECT_NEAR(thrust_n, quarter_weight_n, 0.02);
}

TEST_F(InProcessDutTest, CommandAnswersTheTickItWasAskedFor) {
  HoverFor(3);
  const ActuatorMessage command = dut_.Step(42, 4'000'000).value();
  EXPECT_EQ(command.answers_sequence, 42u);
  EXPECT_EQ(command.stamp.time_ns, 4'000'000);
}

TEST_F(InProcessDutTest, DecodesSensorFramesAndCountsCorruptOnes) {
  rig::TactileSample sample;
  sample.node_id = tactile_bus::kReferenceNodeId;
  ASSERT_TRUE(node_->Send(rig::EncodeTactileSample(sample), 0).ok());
  const std::uint8_t short_payload[3] = {1, 2, 3};
  ASSERT_TRUE(node_->Send(rig::CanFrame::Classic(0x107, short_payload), 0).ok());
  const std::uint8_t unknown[8] = {};
  ASSERT_TRUE(node_->Send(rig::CanFrame::Classic(0x555, unknown), 0).ok());
  ASSERT_TRUE(dut_.Step(0, 10'000'000).ok());
  const DutCounters counters = dut_.counters();
  EXPECT_EQ(counters.can_frames_received, 3u);
  EXPECT_EQ(counters.sensor_samples, 1u);
  EXPECT_EQ(counters.can_frames_rejected, 2u);
}

TEST_F(InProcessDutTest, NonFiniteImuSampleDoesNotReachTheMotors) {
  HoverFor(100);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  dut_.Send(ImuMessage{{101, 101'000'000}, Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d(0, 0, nan)});
  const ActuatorMessage command = dut_.Step(101, 101'000'000).value();
  for (double thrust_n : command.rotor_thrust_n) EXPECT_TRUE(std::isfinite(thrust_n));
  EXPECT_TRUE(command.estimated_position_m.allFinite());
}

TEST_F(InProcessDutTest, KeepsTheFrameOpenUntilAGraspIsCommanded) {
  const ActuatorMessage command = HoverFor(10);
  EXPECT_EQ(command.servo_angle_rad, dut_fw::GraspAdmittanceParams<double>{}.open_angle_rad);
}

// Without tactile nodes the grasp force estimate is never valid, so a regulating grasp holds the
// mission's reference angle instead of winding the servo closed on a force it cannot see.
TEST_F(InProcessDutTest, GraspWithoutAForceEstimateHoldsTheReferenceAngle) {
  HoverFor(1);
  SetpointMessage setpoint = GraspSetpoint();
  setpoint.position_m = Eigen::Vector3d(0, 0, 1);
  dut_.Send(setpoint);
  ActuatorMessage command;
  for (int i = 2; i < 50; ++i) command = dut_.Step(i, i * 1'000'000).value();
  EXPECT_DOUBLE_EQ(command.servo_angle_rad, 0.5);
  EXPECT_FALSE(command.tactile_ready);
}

TEST(InProcessDutAblationTest, WithoutForceFeedbackTheGraspClosesTheFrameOpenLoop) {
  rig::EmulatedBus bus;
  DutFirmware firmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true};
  firmware.grasp.force_feedback = false;
  firmware.grasp.closed_angle_rad = 1.4;
  InProcessDut dut(firmware, bus.Connect("dut"), kControlPeriodS);
  dut.Send(GraspSetpoint());
  EXPECT_DOUBLE_EQ(dut.Step(0, 0).value().servo_angle_rad, 1.4);
}

TEST(InProcessDutInvalidParamsTest, InvalidGraspParamsCommandTheOpenAngleEveryStep) {
  rig::EmulatedBus bus;
  DutFirmware firmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true};
  firmware.grasp.open_angle_rad = 0.2;
  firmware.grasp.mass = std::numeric_limits<double>::quiet_NaN();
  InProcessDut dut(firmware, bus.Connect("dut"), kControlPeriodS);
  dut.Send(GraspSetpoint());

  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(dut.Step(i, i * 1'000'000).value().servo_angle_rad, 0.2);
  }
}

}  // namespace
}  // namespace hilrig::host
