// dut_emu --mavlink: the PX4 SITL stand-in on the simulator link of docs/mavlink.md. MavlinkDut is
// driven directly, message by message, with the rig's hover firmware behind it or with a port that
// records what it is sent: each HIL_SENSOR is answered with one HIL_ACTUATOR_CONTROLS of its time,
// the motors stay still until the arm command, commands are acknowledged, NED/FRD become the rig's
// ENU/FLU, the stale rule fires at exactly 100 repeats, and time only goes forward. One test runs
// RunMavlinkDut in a thread against the test's own TCP listener and UDP port.
#include "dut_emu/mavlink_dut.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <thread>
#include <vector>

#include "host/dut/firmware_config.h"
#include "host/link/dut_config_codec.h"
#include "tests/support/stoppable_thread.h"
#include "tests/support/test_files.h"

namespace hilrig::dut_emu {
namespace {

constexpr double kSensorPeriodS = 0.004;
constexpr std::uint64_t kSensorPeriodUsec = 4000;
constexpr MavlinkSender kGroundStation{255, 190};
constexpr int kAnswerTimeoutMs = 5000;  // a bound on a hung DUT; answers come in microseconds

host::DutFirmware HoverFirmware() {
  return host::DutFirmware{
      host::FirmwareParamsFor(host::QuadrotorParams{}), std::nullopt, {}, true};
}

struct Received {
  mavlink::Frame frame;
  mavlink::AnyMessage message;
};

std::vector<Received> Decode(std::span<const std::uint8_t> bytes) {
  mavlink::FrameParser parser(mavlink::FindWireInfo);
  std::vector<Received> received;
  parser.Feed(bytes, [&received](const mavlink::Frame& frame) {
    std::optional<mavlink::AnyMessage> message = mavlink::DecodeMessage(frame);
    EXPECT_TRUE(message.has_value()) << "message id " << frame.message_id;
    if (message) received.push_back({frame, *message});
  });
  parser.Finish();
  EXPECT_FALSE(parser.Next().has_value());
  EXPECT_EQ(parser.counters().frames_ok, received.size()) << "every byte is a frame";
  EXPECT_EQ(parser.counters().bytes_skipped + parser.counters().crc_failures, 0u);
  return received;
}

std::vector<Received> Decode(const MavlinkFrameBatch& batch) {
  std::vector<std::uint8_t> bytes;
  for (std::size_t i = 0; i < batch.size(); ++i) {
    bytes.insert(bytes.end(), batch.frame(i).begin(), batch.frame(i).end());
  }
  return Decode(bytes);
}

template <typename M>
M Only(const MavlinkFrameBatch& batch) {
  const std::vector<Received> received = Decode(batch);
  EXPECT_EQ(received.size(), 1u);
  if (received.size() != 1 || !std::holds_alternative<M>(received[0].message)) {
    ADD_FAILURE() << "expected one " << M::kName;
    return M{};
  }
  return std::get<M>(received[0].message);
}

// The IMU at rest in FRD: gravity's reaction points up, -z. `jitter` changes the gyro in its last
// bits, as a noisy sensor's readings change from one sample to the next.
mavlink::HilSensor AtRest(std::uint64_t time_usec, int jitter = 0) {
  mavlink::HilSensor sensor;
  sensor.time_usec = time_usec;
  sensor.zacc_m_s2 = -9.81f;
  sensor.xgyro_rad_s = 1e-5f * static_cast<float>(jitter % 2);
  sensor.fields_updated = 0x3F;
  return sensor;
}

// The rig's pose (x east, y north, z up; body x forward, y left) at 1 m up, facing east: in NED,
// 1 m down the z axis and heading east (yaw π/2 about down).
mavlink::Odometry PoseOneMetreUp(std::uint64_t time_usec) {
  mavlink::Odometry odometry;
  odometry.time_usec = time_usec;
  odometry.z_m = -1.0f;
  odometry.q = {static_cast<float>(std::cos(std::numbers::pi / 4)), 0.0f, 0.0f,
                static_cast<float>(std::sin(std::numbers::pi / 4))};
  odometry.frame_id = 1;
  odometry.child_frame_id = 12;
  odometry.estimator_type = 3;
  return odometry;
}

mavlink::SetPositionTargetLocalNed HoldOneMetreUp() {
  mavlink::SetPositionTargetLocalNed target;
  target.z_m = -1.0f;
  target.yaw_rad = static_cast<float>(std::numbers::pi / 2);
  target.type_mask = 0x800;
  target.target_system = 1;
  target.target_component = 1;
  target.coordinate_frame = 1;
  return target;
}

mavlink::CommandLong Command(std::uint16_t id, float param1, float param2 = 0) {
  mavlink::CommandLong command;
  command.command = id;
  command.param1 = param1;
  command.param2 = param2;
  command.target_system = 1;
  command.target_component = 1;
  return command;
}

TEST(MavlinkDutTest, AnswersAHilSensorWithOneActuatorControlsOfItsTime) {
  MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
  for (std::uint64_t step = 1; step <= 3; ++step) {
    const MavlinkReplies& replies =
        dut.Handle(AtRest(step * kSensorPeriodUsec, int(step)), MavlinkLink::kSimulator);
    EXPECT_EQ(replies.end, MavlinkDutEnd::kRunning);
    // No heartbeat before a second of the DUT's time: the step's estimates only.
    EXPECT_TRUE(host::IsTelemetry(Only<mavlink::DebugFloatArray>(replies.api)));
    const std::vector<Received> received = Decode(replies.simulator);
    ASSERT_EQ(received.size(), 1u);
    EXPECT_EQ(received[0].frame.system_id, 1);
    EXPECT_EQ(received[0].frame.component_id, 1);
    EXPECT_EQ(received[0].frame.sequence, step - 1) << "the simulator link's own sequence";
    const auto& controls = std::get<mavlink::HilActuatorControls>(received[0].message);
    EXPECT_EQ(controls.time_usec, step * kSensorPeriodUsec);
    EXPECT_EQ(controls.flags, 1u);
    EXPECT_EQ(controls.mode, 1) << "disarmed";
  }
  EXPECT_EQ(dut.counters().sensor_steps, 3u);
}

TEST(MavlinkDutTest, StaysStillUntilArmedThenHoldsItsWeight) {
  const host::DutFirmware firmware = HoverFirmware();
  MavlinkDut dut(firmware, kSensorPeriodS);
  std::uint64_t time_usec = 0;
  // One step: a pose 1 m up, the IMU at rest.
  const auto step = [&dut, &time_usec]() {
    time_usec += kSensorPeriodUsec;
    dut.Handle(PoseOneMetreUp(time_usec), MavlinkLink::kSimulator);
    const MavlinkReplies& replies =
        dut.Handle(AtRest(time_usec, int(time_usec / kSensorPeriodUsec)), MavlinkLink::kSimulator);
    EXPECT_EQ(replies.end, MavlinkDutEnd::kRunning) << replies.why;
    return Only<mavlink::HilActuatorControls>(replies.simulator);
  };
  dut.Handle(HoldOneMetreUp(), MavlinkLink::kApi, kGroundStation);
  for (int i = 0; i < 10; ++i) {
    const mavlink::HilActuatorControls controls = step();
    for (int motor = 0; motor < 4; ++motor) EXPECT_EQ(controls.controls[motor], 0.0f);
    EXPECT_EQ(controls.mode, 1);
    EXPECT_FLOAT_EQ(controls.controls[4], -1.0f) << "the gripper open";
  }
  const mavlink::CommandAck ack =
      Only<mavlink::CommandAck>(dut.Handle(Command(400, 1), MavlinkLink::kApi, kGroundStation).api);
  EXPECT_EQ(ack.result, 0);
  EXPECT_TRUE(dut.arm_commanded());
  mavlink::HilActuatorControls controls;
  for (int i = 0; i < 20; ++i) controls = step();
  EXPECT_EQ(controls.mode, 129);
  const host::QuadrotorParams vehicle;
  const double weight_share_n = vehicle.body.mass_kg * vehicle.gravity_m_s2 / 4;
  for (int motor = 0; motor < 4; ++motor) {
    const double thrust_n = controls.controls[motor] * firmware.flight.mixer.max_thrust_per_rotor_n;
    EXPECT_GT(controls.controls[motor], 0.0f);
    EXPECT_LE(controls.controls[motor], 1.0f);
    EXPECT_NEAR(thrust_n, weight_share_n, 0.15 * weight_share_n) << "motor " << motor;
  }
  // Disarmed again, the motors stop on the next step.
  dut.Handle(Command(400, 0), MavlinkLink::kApi, kGroundStation);
  controls = step();
  EXPECT_EQ(controls.mode, 1);
  for (int motor = 0; motor < 4; ++motor) EXPECT_EQ(controls.controls[motor], 0.0f);
}

TEST(MavlinkDutTest, AcknowledgesEachCommandAndReportsItsModeInTheHeartbeat) {
  MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
  const mavlink::Heartbeat standby = Only<mavlink::Heartbeat>(dut.Announce().api);
  EXPECT_EQ(standby.type, 2);
  EXPECT_EQ(standby.autopilot, 12);
  EXPECT_EQ(standby.system_status, 3);
  EXPECT_EQ(standby.base_mode & 128, 0);

  struct Case {
    mavlink::CommandLong command;
    MavResult result;
  };
  for (const Case& c :
       {Case{Command(400, 1), MavResult::kAccepted}, Case{Command(176, 1, 6), MavResult::kAccepted},
        Case{Command(400, 2), MavResult::kDenied},
        Case{Command(511, 1), MavResult::kUnsupported}}) {
    const MavlinkReplies& replies = dut.Handle(c.command, MavlinkLink::kApi, kGroundStation);
    EXPECT_TRUE(replies.simulator.empty());
    const std::vector<Received> received = Decode(replies.api);
    ASSERT_EQ(received.size(), 1u);
    const auto& ack = std::get<mavlink::CommandAck>(received[0].message);
    EXPECT_EQ(ack.command, c.command.command);
    EXPECT_EQ(ack.result, static_cast<std::uint8_t>(c.result)) << "command " << c.command.command;
    EXPECT_EQ(ack.target_system, 255);
    EXPECT_EQ(ack.target_component, 190);
  }
  const mavlink::Heartbeat armed = Only<mavlink::Heartbeat>(dut.Announce().api);
  EXPECT_EQ(armed.base_mode, 128 | 1);
  EXPECT_EQ(armed.custom_mode, 6u << 16) << "PX4's offboard main mode";
  EXPECT_EQ(armed.system_status, 4);

  // A command for another vehicle is not this one's to answer.
  mavlink::CommandLong elsewhere = Command(400, 0);
  elsewhere.target_system = 7;
  EXPECT_TRUE(dut.Handle(elsewhere, MavlinkLink::kApi, kGroundStation).api.empty());
  EXPECT_TRUE(dut.arm_commanded());
  EXPECT_EQ(dut.counters().commands, 4u);
  EXPECT_EQ(dut.counters().ignored, 1u);
}

TEST(MavlinkDutTest, SendsAHeartbeatOncePerSecondOfTheDutsTime) {
  MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
  const std::vector<Received> announced = Decode(dut.Announce().api);
  ASSERT_EQ(announced.size(), 1u);
  EXPECT_EQ(announced[0].frame.sequence, 0);
  std::vector<std::uint64_t> heartbeat_times_usec;
  int api_frames = 0;
  int telemetry_frames = 0;
  for (std::uint64_t step = 1; step <= 600; ++step) {
    const std::uint64_t time_usec = step * kSensorPeriodUsec;
    const MavlinkReplies& replies =
        dut.Handle(AtRest(time_usec, int(step)), MavlinkLink::kSimulator);
    ASSERT_EQ(replies.end, MavlinkDutEnd::kRunning) << replies.why;
    const std::vector<Received> received = Decode(replies.api);
    for (const Received& r : received) {
      EXPECT_EQ(r.frame.sequence, static_cast<std::uint8_t>(++api_frames)) << "the API sequence";
      if (std::holds_alternative<mavlink::Heartbeat>(r.message)) {
        heartbeat_times_usec.push_back(time_usec);
        continue;
      }
      // Every step's estimates, ahead of its answer.
      const auto* telemetry = std::get_if<mavlink::DebugFloatArray>(&r.message);
      ASSERT_NE(telemetry, nullptr);
      EXPECT_TRUE(host::IsTelemetry(*telemetry));
      EXPECT_EQ(telemetry->time_usec, time_usec);
      ++telemetry_frames;
    }
  }
  EXPECT_EQ(heartbeat_times_usec, (std::vector<std::uint64_t>{1'000'000, 2'000'000}));
  EXPECT_EQ(telemetry_frames, 600);
}

// A DUT port that records what it is sent and answers with fixed thrusts and servo angle.
class RecordingPort final : public host::DutPort {
 public:
  explicit RecordingPort(std::vector<host::DutInput>& inputs) : inputs_(inputs) {}
  void Send(const host::DutInput& input) override { inputs_.push_back(input); }
  rig::Result<host::ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override {
    steps.emplace_back(tick, now_ns);
    host::ActuatorMessage command;
    command.answers_sequence = tick;
    command.rotor_thrust_n = {2.0, 10.0, -1.0, NAN};
    command.armed = true;
    command.servo_angle_rad = 0.8;
    return command;
  }
  host::DutCounters counters() const override { return {}; }
  std::string description() const override { return "recording port"; }

  std::vector<std::pair<std::uint64_t, std::int64_t>> steps;

 private:
  std::vector<host::DutInput>& inputs_;
};

TEST(MavlinkDutTest, DeliversPosesAndSetpointsWithTheNextSensorStepAndNormalisesItsOutputs) {
  std::vector<host::DutInput> inputs;
  auto port = std::make_unique<RecordingPort>(inputs);
  RecordingPort& recording = *port;
  MavlinkDut dut(std::move(port), host::ActuatorScale{4.0, 0.0, 1.6});
  dut.Handle(PoseOneMetreUp(1'000), MavlinkLink::kSimulator);
  dut.Handle(HoldOneMetreUp(), MavlinkLink::kApi, kGroundStation);
  EXPECT_TRUE(inputs.empty()) << "held until the step whose time is their delivery time";
  mavlink::HilSensor sensor = AtRest(8'000);
  sensor.xacc_m_s2 = 0.5f;
  sensor.ygyro_rad_s = 0.25f;
  const mavlink::HilActuatorControls disarmed =
      Only<mavlink::HilActuatorControls>(dut.Handle(sensor, MavlinkLink::kSimulator).simulator);
  for (int motor = 0; motor < 4; ++motor) EXPECT_EQ(disarmed.controls[motor], 0.0f);
  EXPECT_FLOAT_EQ(disarmed.controls[4], 0.0f) << "the servo midway between open and closed";

  ASSERT_EQ(inputs.size(), 3u);
  const auto& vio = std::get<host::VioMessage>(inputs[0]);
  EXPECT_EQ(vio.stamp.sequence, 0u);
  EXPECT_EQ(vio.stamp.time_ns, 8'000'000);
  EXPECT_EQ(vio.capture_time_ns, 1'000'000);
  const auto& setpoint = std::get<host::SetpointMessage>(inputs[1]);
  EXPECT_EQ(setpoint.stamp.time_ns, 8'000'000);
  EXPECT_EQ(setpoint.position_m, Eigen::Vector3d(0, 0, 1));
  const auto& imu = std::get<host::ImuMessage>(inputs[2]);
  EXPECT_EQ(imu.stamp.time_ns, 8'000'000);
  EXPECT_EQ(imu.accel_m_s2, Eigen::Vector3d(0.5, 0, 9.81f));
  EXPECT_EQ(imu.gyro_rad_s, Eigen::Vector3d(0, -0.25, 0));
  ASSERT_EQ(recording.steps.size(), 1u);
  EXPECT_EQ(recording.steps[0], (std::pair<std::uint64_t, std::int64_t>{1, 8'000'000}));

  dut.Handle(Command(400, 1), MavlinkLink::kApi, kGroundStation);
  const mavlink::HilActuatorControls armed = Only<mavlink::HilActuatorControls>(
      dut.Handle(AtRest(12'000), MavlinkLink::kSimulator).simulator);
  EXPECT_EQ(armed.mode, 129);
  EXPECT_FLOAT_EQ(armed.controls[0], 0.5f);
  EXPECT_FLOAT_EQ(armed.controls[1], 1.0f) << "clamped";
  EXPECT_FLOAT_EQ(armed.controls[2], 0.0f) << "clamped";
  EXPECT_FLOAT_EQ(armed.controls[3], 0.0f) << "not finite: still";
  EXPECT_EQ(recording.steps.back().first, 2u);
  EXPECT_EQ(inputs.size(), 4u) << "only the IMU reading is new";
}

TEST(MavlinkDutTest, TakesTheGraspFromTheGripperCommandWithTheNextStep) {
  std::vector<host::DutInput> inputs;
  MavlinkDut dut(std::make_unique<RecordingPort>(inputs), host::ActuatorScale{4.0, 0.0, 1.6});
  dut.Handle(HoldOneMetreUp(), MavlinkLink::kApi, kGroundStation);
  mavlink::CommandLong grab = Command(211, 1, 1);
  grab.param3 = 4.0f;
  grab.param4 = 0.5f;
  const auto ack =
      Only<mavlink::CommandAck>(dut.Handle(grab, MavlinkLink::kApi, kGroundStation).api);
  EXPECT_EQ(ack.command, 211);
  EXPECT_EQ(ack.result, 0) << "accepted";
  dut.Handle(AtRest(4'000), MavlinkLink::kSimulator);
  ASSERT_EQ(inputs.size(), 2u);
  const auto& grasping = std::get<host::SetpointMessage>(inputs[0]);
  EXPECT_EQ(grasping.position_m, Eigen::Vector3d(0, 0, 1)) << "the position target stays";
  EXPECT_TRUE(grasping.grasp_regulate);
  EXPECT_EQ(grasping.grasp_force_n, 4.0);
  EXPECT_EQ(grasping.grasp_reference_angle_rad, 0.5);

  // A new position target keeps the grasp; a release opens it.
  mavlink::SetPositionTargetLocalNed higher = HoldOneMetreUp();
  higher.z_m = -2.0f;
  dut.Handle(higher, MavlinkLink::kApi, kGroundStation);
  dut.Handle(AtRest(8'000, 1), MavlinkLink::kSimulator);
  ASSERT_EQ(inputs.size(), 4u);
  EXPECT_TRUE(std::get<host::SetpointMessage>(inputs[2]).grasp_regulate);
  EXPECT_EQ(std::get<host::SetpointMessage>(inputs[2]).position_m, Eigen::Vector3d(0, 0, 2));
  dut.Handle(Command(211, 1, 0), MavlinkLink::kApi, kGroundStation);
  dut.Handle(AtRest(12'000), MavlinkLink::kSimulator);
  ASSERT_EQ(inputs.size(), 6u);
  EXPECT_FALSE(std::get<host::SetpointMessage>(inputs[4]).grasp_regulate);

  mavlink::CommandLong bad = grab;
  bad.param3 = NAN;
  EXPECT_EQ(
      Only<mavlink::CommandAck>(dut.Handle(bad, MavlinkLink::kApi, kGroundStation).api).result, 2)
      << "denied: a force that is no number";
  dut.Handle(AtRest(16'000, 1), MavlinkLink::kSimulator);
  EXPECT_EQ(inputs.size(), 7u) << "no setpoint: the grasp did not change";
}

TEST(MavlinkDutTest, PutsCanFramesOnTheControllersBusAndReportsItsEstimatesEachStep) {
  MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
  const std::array<std::uint8_t, 2> payload = {1, 2};
  mavlink::CanFrame can = *host::CanFrameMessageFrom(rig::CanFrame::Classic(0x7F0, payload));
  EXPECT_TRUE(dut.Handle(can, MavlinkLink::kSimulator).simulator.empty()) << "no answer";
  mavlink::CanFrame broken = can;
  broken.len = 9;
  dut.Handle(broken, MavlinkLink::kSimulator);
  dut.Handle(can, MavlinkLink::kApi, kGroundStation);  // not the link CAN frames come on
  EXPECT_EQ(dut.counters().can_frames, 1u);
  EXPECT_EQ(dut.counters().ignored, 2u);
  EXPECT_EQ(dut.controller_counters().can_frames_received, 0u) << "read at the next step";

  const MavlinkReplies& replies = dut.Handle(AtRest(4'000), MavlinkLink::kSimulator);
  EXPECT_EQ(dut.controller_counters().can_frames_received, 1u);
  EXPECT_EQ(dut.controller_counters().can_frames_rejected, 1u) << "no node of the rig has 0x7F0";
  const auto telemetry = Only<mavlink::DebugFloatArray>(replies.api);
  EXPECT_TRUE(host::IsTelemetry(telemetry));
  EXPECT_EQ(telemetry.time_usec, 4'000u);
  EXPECT_EQ(telemetry.data[7], 0.0f) << "the pads are not zeroed yet";
}

TEST(MavlinkDutTest, HandsTheFixMagnetometerAndBarometerToTheControllerWithTheStep) {
  std::vector<host::DutInput> inputs;
  MavlinkDut dut(std::make_unique<RecordingPort>(inputs), host::ActuatorScale{4.0, 0.0, 1.6});
  host::GnssMessage fix;
  fix.latitude_deg = 47.3769;
  fix.altitude_m = 408;
  fix.satellites = 12;
  dut.Handle(host::HilGpsFrom(fix, host::kRunEpochUnixUsec), MavlinkLink::kSimulator);
  mavlink::HilGps no_fix = host::HilGpsFrom(fix, host::kRunEpochUnixUsec);
  no_fix.fix_type = 0;
  dut.Handle(no_fix, MavlinkLink::kSimulator);
  EXPECT_EQ(dut.counters().gps_fixes, 1u);
  EXPECT_EQ(dut.counters().ignored, 1u) << "no fix, nothing to take";
  EXPECT_TRUE(inputs.empty());

  host::ImuMessage imu;
  imu.accel_m_s2 = {0, 0, 9.81};
  host::MagnetometerMessage mag;
  mag.field_body_t = {24e-6, 0, -41.6e-6};
  host::BarometerMessage baro;
  baro.pressure_pa = 96500;
  dut.Handle(host::HilSensorFrom(imu, 4'000, &mag, &baro), MavlinkLink::kSimulator);
  ASSERT_EQ(inputs.size(), 4u);
  const auto& gnss = std::get<host::GnssMessage>(inputs[0]);
  EXPECT_NEAR(gnss.latitude_deg, 47.3769, 1e-7);
  EXPECT_EQ(gnss.stamp.time_ns, 4'000'000);
  EXPECT_NEAR(std::get<host::MagnetometerMessage>(inputs[1]).field_body_t.x(), 24e-6, 1e-11);
  EXPECT_NEAR(std::get<host::BarometerMessage>(inputs[2]).pressure_pa, 96500, 0.01);
  EXPECT_TRUE(std::holds_alternative<host::ImuMessage>(inputs[3]));

  // A step whose fields_updated has only the IMU hands over only the IMU.
  dut.Handle(host::HilSensorFrom(imu, 8'000), MavlinkLink::kSimulator);
  ASSERT_EQ(inputs.size(), 5u);
  EXPECT_TRUE(std::holds_alternative<host::ImuMessage>(inputs[4]));
}

TEST(MavlinkDutTest, TheStaleRuleFiresAtExactlyOneHundredIdenticalReadings) {
  MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
  std::uint64_t time_usec = 0;
  const auto send = [&dut, &time_usec](int jitter) -> const MavlinkReplies& {
    time_usec += kSensorPeriodUsec;
    return dut.Handle(AtRest(time_usec, jitter), MavlinkLink::kSimulator);
  };
  // 99 the same, then a different one: no verdict, and the count starts over.
  for (int i = 0; i < 99; ++i) ASSERT_EQ(send(0).end, MavlinkDutEnd::kRunning) << i;
  ASSERT_EQ(send(1).end, MavlinkDutEnd::kRunning);
  for (int reading = 2; reading <= 99; ++reading) {
    const MavlinkReplies& replies = send(1);
    ASSERT_EQ(replies.end, MavlinkDutEnd::kRunning) << "reading " << reading;
    EXPECT_EQ(replies.simulator.size(), 1u);
  }
  const MavlinkReplies& stale = send(1);
  EXPECT_EQ(stale.end, MavlinkDutEnd::kSensorsStale);
  EXPECT_EQ(stale.why,
            "the accelerometer and gyro readings repeated 100 times: sensors stale (PX4 marks such "
            "a sensor stale; the scene needs IMU noise)");
  EXPECT_TRUE(stale.simulator.empty()) << "a stale step is not answered";
  EXPECT_EQ(send(0).end, MavlinkDutEnd::kSensorsStale) << "it takes nothing after its end";
}

TEST(MavlinkDutTest, RefusesTimeThatIsZeroOrDoesNotGoForward) {
  {
    MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
    EXPECT_EQ(dut.Handle(AtRest(0), MavlinkLink::kSimulator).end, MavlinkDutEnd::kTimeZero);
  }
  {
    MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
    ASSERT_EQ(dut.Handle(AtRest(8'000, 0), MavlinkLink::kSimulator).end, MavlinkDutEnd::kRunning);
    const MavlinkReplies& backwards = dut.Handle(AtRest(4'000, 1), MavlinkLink::kSimulator);
    EXPECT_EQ(backwards.end, MavlinkDutEnd::kTimeNotAdvancing);
    EXPECT_EQ(backwards.why,
              "HIL_SENSOR time_usec 4000 does not come after the previous one, 8000");
    EXPECT_TRUE(backwards.simulator.empty());
  }
  {
    MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
    ASSERT_EQ(dut.Handle(AtRest(8'000, 0), MavlinkLink::kSimulator).end, MavlinkDutEnd::kRunning);
    EXPECT_EQ(dut.Handle(AtRest(8'000, 1), MavlinkLink::kSimulator).end,
              MavlinkDutEnd::kTimeNotAdvancing);
  }
}

TEST(MavlinkDutTest, AFrameTheCodecCannotDecodeEndsIt) {
  MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
  mavlink::Frame unknown;
  unknown.message_id = 12345;
  unknown.payload_length = 1;
  const MavlinkReplies& replies = dut.HandleFrame(unknown, MavlinkLink::kSimulator);
  EXPECT_EQ(replies.end, MavlinkDutEnd::kUndecodable);
  EXPECT_NE(replies.why.find("12345"), std::string::npos) << replies.why;
}

TEST(MavlinkDutTest, IgnoresMessagesOnTheWrongLink) {
  MavlinkDut dut(HoverFirmware(), kSensorPeriodS);
  EXPECT_TRUE(dut.Handle(AtRest(4'000), MavlinkLink::kApi).simulator.empty());
  EXPECT_TRUE(dut.Handle(Command(400, 1), MavlinkLink::kSimulator).api.empty());
  EXPECT_FALSE(dut.arm_commanded());
  EXPECT_EQ(dut.counters().ignored, 2u);
  EXPECT_EQ(dut.counters().sensor_steps, 0u);
}

TEST(MavlinkDutArgsTest, ParsesTheThreeOptions) {
  auto options = ParseMavlinkArgs(
      {"dut_emu", "--mavlink", "127.0.0.1:4560", "--api", "[::1]:14540", "--config", "dut.pb"});
  ASSERT_TRUE(options.ok()) << options.error().message;
  EXPECT_EQ(options.value().simulator_host, "127.0.0.1");
  EXPECT_EQ(options.value().simulator_port, 4560);
  EXPECT_EQ(options.value().api_host, "::1");
  EXPECT_EQ(options.value().api_port, 14540);
  EXPECT_EQ(options.value().config_path, "dut.pb");
  for (const std::vector<std::string>& bad : std::vector<std::vector<std::string>>{
           {"dut_emu", "--mavlink", "127.0.0.1:4560", "--api", "127.0.0.1:14540"},
           {"dut_emu", "--mavlink", "4560", "--api", "127.0.0.1:14540", "--config", "c"},
           {"dut_emu", "--mavlink", "h:0", "--api", "127.0.0.1:14540", "--config", "c"},
           {"dut_emu", "--mavlink", "h:1", "--api", "127.0.0.1:x", "--config", "c"},
           {"dut_emu", "--mavlink", "h:1", "--api", "h:2", "--config", "c", "--link", "h:3"}}) {
    EXPECT_FALSE(ParseMavlinkArgs(bad).ok()) << bad.size();
  }
}

// The test's side of the links: a TCP listener and a UDP socket on loopback.
class OwnedFd {
 public:
  explicit OwnedFd(int fd = -1) : fd_(fd) {}
  OwnedFd(const OwnedFd&) = delete;
  OwnedFd& operator=(const OwnedFd&) = delete;
  ~OwnedFd() { Reset(); }
  void Reset(int fd = -1) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

std::uint16_t BindLoopback(int fd) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  socklen_t length = sizeof address;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  return ntohs(address.sin_port);
}

bool WaitReadable(int fd) {
  pollfd in{fd, POLLIN, 0};
  return ::poll(&in, 1, kAnswerTimeoutMs) == 1;
}

// As the rig sends it: system 1, component 51 on the simulator link; a ground station, system 255,
// component 190, on the API link.
std::vector<std::uint8_t> Encode(const mavlink::AnyMessage& message, std::uint8_t sequence,
                                 MavlinkSender sender = {1, 51}) {
  std::vector<std::uint8_t> bytes(mavlink::kMaxFrameBytes);
  bytes.resize(
      mavlink::EncodeMessage(message, sequence, sender.system_id, sender.component_id, bytes));
  return bytes;
}

// The next `count` messages on a stream socket, parsed in whatever chunks they come.
std::vector<mavlink::AnyMessage> ReadStream(int fd, mavlink::FrameParser& parser,
                                            std::size_t count) {
  std::vector<mavlink::AnyMessage> messages;
  std::array<std::uint8_t, 512> chunk{};
  while (messages.size() < count) {
    while (std::optional<mavlink::Frame> frame = parser.Next()) {
      messages.push_back(*mavlink::DecodeMessage(*frame));
    }
    if (messages.size() >= count) break;
    if (!WaitReadable(fd)) break;
    const ssize_t got = ::recv(fd, chunk.data(), chunk.size(), 0);
    if (got <= 0) break;
    EXPECT_EQ(parser.Push({chunk.data(), std::size_t(got)}), std::size_t(got));
  }
  return messages;
}

std::string WriteConfig() {
  const std::filesystem::path path = host::FreshTestDir("mavlink_dut_") / "dut_config.pb";
  std::string bytes;
  EXPECT_TRUE(host::ToDutConfig(HoverFirmware(), kSensorPeriodS).SerializeToString(&bytes));
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

TEST(MavlinkDutLoopTest, FliesOverLoopbackSocketsAndEndsWhenTheSimulatorCloses) {
  OwnedFd listener(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  OwnedFd api(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  MavlinkDutOptions options;
  options.simulator_host = "127.0.0.1";
  options.simulator_port = BindLoopback(listener.get());
  ASSERT_EQ(::listen(listener.get(), 1), 0);
  options.api_host = "127.0.0.1";
  options.api_port = BindLoopback(api.get());
  options.config_path = WriteConfig();
  std::ostringstream log;
  test_support::StoppableThread dut(
      [&](const std::atomic<bool>* stop) { return RunMavlinkDut(options, stop, log); });

  // The heartbeat announces the DUT; the rig answers to where it came from.
  ASSERT_TRUE(WaitReadable(api.get())) << log.str();
  std::array<std::uint8_t, 512> datagram{};
  sockaddr_in dut_api{};
  socklen_t dut_api_length = sizeof dut_api;
  const ssize_t got = ::recvfrom(api.get(), datagram.data(), datagram.size(), 0,
                                 reinterpret_cast<sockaddr*>(&dut_api), &dut_api_length);
  ASSERT_GT(got, 0);
  const std::vector<Received> hello = Decode({datagram.data(), std::size_t(got)});
  ASSERT_EQ(hello.size(), 1u);
  EXPECT_EQ(std::get<mavlink::Heartbeat>(hello[0].message).autopilot, 12);
  EXPECT_EQ(hello[0].frame.system_id, 1);

  ASSERT_TRUE(WaitReadable(listener.get())) << log.str();
  OwnedFd simulator(::accept(listener.get(), nullptr, nullptr));
  ASSERT_GE(simulator.get(), 0);

  // The API link's commands of the first step, one datagram each, before its HIL_SENSOR.
  std::uint8_t api_sequence = 0;
  for (const mavlink::AnyMessage& message :
       {mavlink::AnyMessage(HoldOneMetreUp()), mavlink::AnyMessage(Command(400, 1)),
        mavlink::AnyMessage(Command(176, 1, 6))}) {
    const std::vector<std::uint8_t> frame = Encode(message, api_sequence++, kGroundStation);
    ASSERT_EQ(::sendto(api.get(), frame.data(), frame.size(), 0,
                       reinterpret_cast<sockaddr*>(&dut_api), dut_api_length),
              ssize_t(frame.size()));
  }
  mavlink::FrameParser answers(mavlink::FindWireInfo);
  std::uint8_t sequence = 0;
  constexpr std::uint64_t kSteps = 25;
  mavlink::HilActuatorControls last;
  for (std::uint64_t step = 1; step <= kSteps; ++step) {
    const std::uint64_t time_usec = step * kSensorPeriodUsec;
    std::vector<std::uint8_t> bytes = Encode(PoseOneMetreUp(time_usec), sequence++);
    const std::vector<std::uint8_t> sensor = Encode(AtRest(time_usec, int(step)), sequence++);
    bytes.insert(bytes.end(), sensor.begin(), sensor.end());
    // The first step a byte at a time: the DUT parses whatever chunks TCP delivers.
    const std::size_t chunk = step == 1 ? 1 : bytes.size();
    for (std::size_t at = 0; at < bytes.size(); at += chunk) {
      const std::size_t size = std::min(chunk, bytes.size() - at);
      ASSERT_EQ(::send(simulator.get(), bytes.data() + at, size, MSG_NOSIGNAL), ssize_t(size));
    }
    const std::vector<mavlink::AnyMessage> answer = ReadStream(simulator.get(), answers, 1);
    ASSERT_EQ(answer.size(), 1u) << "step " << step << ": " << log.str();
    last = std::get<mavlink::HilActuatorControls>(answer[0]);
    EXPECT_EQ(last.time_usec, time_usec);
  }
  EXPECT_EQ(last.mode, 129);
  for (int motor = 0; motor < 4; ++motor) EXPECT_GT(last.controls[motor], 0.0f);

  // Both commands were answered before the first step.
  for (int ack = 0; ack < 2; ++ack) {
    ASSERT_TRUE(WaitReadable(api.get()));
    const ssize_t size = ::recv(api.get(), datagram.data(), datagram.size(), 0);
    const std::vector<Received> received = Decode({datagram.data(), std::size_t(size)});
    ASSERT_EQ(received.size(), 1u);
    const auto& ack = std::get<mavlink::CommandAck>(received[0].message);
    EXPECT_EQ(ack.result, 0);
    EXPECT_EQ(ack.target_system, 255);
  }

  simulator.Reset();
  EXPECT_EQ(dut.Join(), kExitOk) << log.str();
  EXPECT_EQ(log.str(), "dut_emu: the simulator closed the link after 25 steps\n");
}

TEST(MavlinkDutLoopTest, NamesTheSimulatorAddressWhenNobodyListens) {
  OwnedFd api(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  OwnedFd unused(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  MavlinkDutOptions options;
  options.simulator_host = "127.0.0.1";
  options.simulator_port = BindLoopback(unused.get());  // bound, never listening: refused
  options.api_host = "127.0.0.1";
  options.api_port = BindLoopback(api.get());
  options.config_path = WriteConfig();
  options.connect_timeout_ms = 50;
  std::ostringstream log;
  EXPECT_EQ(RunMavlinkDut(options, nullptr, log), kExitFailed);
  EXPECT_NE(log.str().find("127.0.0.1:" + std::to_string(options.simulator_port)),
            std::string::npos)
      << log.str();
}

TEST(MavlinkDutLoopTest, ABadConfigFileIsAnError) {
  MavlinkDutOptions options;
  options.simulator_host = "127.0.0.1";
  options.simulator_port = 1;
  options.api_host = "127.0.0.1";
  options.api_port = 1;
  options.config_path = (host::FreshTestDir("mavlink_dut_") / "missing.pb").string();
  std::ostringstream log;
  EXPECT_EQ(RunMavlinkDut(options, nullptr, log), kExitFailed);
  EXPECT_NE(log.str().find("--config"), std::string::npos) << log.str();
}

}  // namespace
}  // namespace hilrig::dut_emu
