// dut_link/serial_session.h with a controller of its own (not dut_fw's), as a team's DUT uses it:
// what Configure is told of the run and the vehicle, a refusal becoming the Bye's reason, every
// input reaching the controller in order with the step's time, and the controller's output on the
// wire as it returned it.
#include "dut_link/controller.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "dut_link/serial_session.h"
#include "tests/support/serial_dut_fakes.h"
#include "tests/support/serial_step_script.h"

namespace hilrig::dut_link {
namespace {

using dut_fw::InputsAt;
using dut_fw::kPeriodNs;
using dut_fw::kPeriodS;

// Keeps what it is told; answers every step with the same output.
class RecordingController final : public Controller {
 public:
  const char* Configure(const RunDescription& run) override {
    ++configured;
    this->run = run;
    config_bytes = run.config.size();
    return refusal;
  }
  void OnImu(const ImuSample& imu) override { imu_times_ns.push_back(imu.time_ns); }
  void OnVio(const VioSample& vio) override { vio_positions_m.push_back(vio.position_m); }
  void OnSetpoint(const Setpoint& setpoint) override { setpoints.push_back(setpoint); }
  void OnCanFrame(const CanFrameIn& frame) override { can_frames.push_back(frame); }
  StepOutput Step(std::int64_t now_ns) override {
    step_times_ns.push_back(now_ns);
    return output;
  }

  const char* refusal = nullptr;
  StepOutput output;
  int configured = 0;
  RunDescription run;
  std::size_t config_bytes = 0;
  std::vector<std::int64_t> imu_times_ns;
  std::vector<Vec3f> vio_positions_m;
  std::vector<Setpoint> setpoints;
  std::vector<CanFrameIn> can_frames;
  std::vector<std::int64_t> step_times_ns;
};

class ControllerTest : public ::testing::Test {
 protected:
  proto::LinkMessage Exchange(const proto::LinkMessage& message) {
    for (const std::uint8_t byte : dut_fw::LineFrame(message)) session_.OnLinkByte(byte);
    std::vector<proto::LinkMessage> answers = sink_.Take();
    EXPECT_EQ(answers.size(), 1u);
    return answers.empty() ? proto::LinkMessage() : answers.front();
  }

  proto::LinkMessage config_ = dut_fw::Config(dut_fw::SixPadFirmware());
  dut_fw::RecordingSink sink_;
  dut_fw::QueueByteSource bridge_;
  dut_fw::SteppingClock clock_;
  dut_fw::SteppingCycleCounter cycles_;
  TargetDescription target_{"own controller", "bench pc", 0, 0, 0, 0, {}};
  RecordingController controller_;
  SerialDutSession session_{controller_, sink_, bridge_, clock_, cycles_, target_};
};

TEST_F(ControllerTest, ConfigureIsToldTheRunAndTheVehicle) {
  ASSERT_TRUE(Exchange(dut_fw::Hello()).has_hello());
  ASSERT_TRUE(Exchange(config_).has_target_info());
  const proto::FlightFirmware& flight = config_.config().flight();
  EXPECT_EQ(controller_.configured, 1);
  EXPECT_EQ(controller_.run.control_period_s, kPeriodS);
  EXPECT_EQ(controller_.run.vehicle.mass_kg, flight.position_mass_kg());
  EXPECT_EQ(controller_.run.vehicle.gravity_m_s2, flight.position_gravity_m_s2());
  EXPECT_EQ(controller_.run.vehicle.inertia_kg_m2[1], flight.attitude_inertia_kg_m2().y());
  EXPECT_EQ(controller_.run.vehicle.arm_length_m, flight.mixer_arm_length_m());
  EXPECT_EQ(controller_.run.vehicle.torque_per_thrust_m, flight.mixer_torque_per_thrust_m());
  EXPECT_EQ(controller_.run.vehicle.max_thrust_per_rotor_n, flight.mixer_max_thrust_per_rotor_n());
  EXPECT_GT(controller_.run.vehicle.mass_kg, 0.0);
  EXPECT_EQ(controller_.config_bytes, config_.config().ByteSizeLong());
  EXPECT_EQ(session_.phase(), SerialDutPhase::kRunning);
}

TEST_F(ControllerTest, ARefusalIsTheByesReason) {
  controller_.refusal = "this controller flies hexacopters only";
  ASSERT_TRUE(Exchange(dut_fw::Hello()).has_hello());
  const proto::LinkMessage bye = Exchange(config_);
  ASSERT_TRUE(bye.has_bye());
  EXPECT_TRUE(bye.bye().error());
  EXPECT_EQ(bye.bye().reason(), "this controller flies hexacopters only");
  EXPECT_EQ(session_.phase(), SerialDutPhase::kAwaitHello);
}

TEST_F(ControllerTest, ANonPositiveControlPeriodIsRefusedWhateverTheControllerSays) {
  config_.mutable_config()->set_control_period_s(0);
  ASSERT_TRUE(Exchange(dut_fw::Hello()).has_hello());
  const proto::LinkMessage bye = Exchange(config_);
  ASSERT_TRUE(bye.has_bye());
  EXPECT_EQ(bye.bye().reason(), "dut config control period must be positive and finite");
}

TEST_F(ControllerTest, InputsReachTheControllerAndItsOutputTheWire) {
  controller_.output.rotor_thrust_n = {1.25f, 1.5f, 1.75f, 2.0f};
  controller_.output.armed = true;
  controller_.output.estimated_position_m = {0.5f, -0.25f, 1.0f};
  ASSERT_TRUE(Exchange(dut_fw::Hello()).has_hello());
  ASSERT_TRUE(Exchange(config_).has_target_info());
  constexpr std::uint64_t kTicks = 40;
  for (std::uint64_t tick = 0; tick < kTicks; ++tick) {
    const dut_fw::TickInputs in = InputsAt(tick);
    bridge_.bytes.insert(bridge_.bytes.end(), in.bridge.begin(), in.bridge.end());
    const proto::LinkMessage answer = Exchange(in.step);
    ASSERT_TRUE(answer.has_serial_command());
    const proto::SerialCommand& command = answer.serial_command();
    EXPECT_EQ(command.answers_tick(), tick);
    ASSERT_EQ(command.rotor_thrust_n_size(), 4);
    EXPECT_EQ(command.rotor_thrust_n(3), 2.0f);
    EXPECT_TRUE(command.armed());
    EXPECT_EQ(command.estimated_position_m(1), -0.25f);
  }
  // One IMU sample per tick, stamped 0.2 ms before the step; a VIO pose every tenth tick.
  ASSERT_EQ(controller_.imu_times_ns.size(), kTicks);
  EXPECT_EQ(controller_.imu_times_ns[5], 5 * kPeriodNs - 200'000);
  ASSERT_EQ(controller_.step_times_ns.size(), kTicks);
  EXPECT_EQ(controller_.step_times_ns[3], 3 * kPeriodNs - 1234);
  EXPECT_EQ(controller_.vio_positions_m.size(), kTicks / 10);
  // The second setpoint changes only the grasp; the position is kept from the first.
  ASSERT_EQ(controller_.setpoints.size(), 2u);
  EXPECT_EQ(controller_.setpoints[1].position_m[2], 1.0f);
  EXPECT_TRUE(controller_.setpoints[1].grasp_regulate);
  EXPECT_EQ(controller_.setpoints[1].grasp_force_n, 0.6f);
  // Every node's sample every fourth tick: the reference node and six pads.
  ASSERT_EQ(controller_.can_frames.size(), 7u * kTicks / 4);
  EXPECT_EQ(controller_.can_frames[7].time_ns, 4 * kPeriodNs);
}

}  // namespace
}  // namespace hilrig::dut_link
