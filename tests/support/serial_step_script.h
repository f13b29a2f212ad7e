// A runner's script for tests of the DUT's side of the serial link: the handshake's messages and
// a few hundred ticks of a hover with a grasp (TickInputs: the SerialStep and the bridge bytes of
// each tick), with DirectDut, the DutCore a correct DUT must match, fed the very same inputs.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dut_fw/dut_config_decoder.h"
#include "dut_fw/dut_core.h"
#include "dut_fw/sensor_node.h"
#include "host/link/dut_config_codec.h"
#include "host/link/hil_messages.h"
#include "proto/hil_link.pb.h"
#include "tests/support/six_pad_tactile.h"

namespace hilrig::dut_fw {

constexpr double kPeriodS = 1e-3;
constexpr std::int64_t kPeriodNs = 1'000'000;

inline proto::LinkMessage Hello(std::uint32_t version = host::kHilLinkProtocolVersion,
                                proto::Hello::Role role = proto::Hello::RUNNER) {
  proto::LinkMessage message;
  message.mutable_hello()->mutable_header()->set_protocol_version(version);
  message.mutable_hello()->set_role(role);
  return message;
}

inline proto::LinkMessage Config(const host::DutFirmware& firmware) {
  proto::LinkMessage message;
  *message.mutable_config() = host::ToDutConfig(firmware, kPeriodS);
  return message;
}

inline proto::LinkMessage Bye() {
  proto::LinkMessage message;
  message.mutable_bye()->mutable_header()->set_protocol_version(host::kHilLinkProtocolVersion);
  return message;
}

// The inputs of tick `tick` of a hover with a grasp: IMU every tick, VIO every tenth, a setpoint
// at 0 and a changed one at 30 (only what changed), and a sample of every node every fourth, the
// pads loaded from 300 on (written to the bridge). DirectDut feeds a DutCore the same inputs.
struct TickInputs {
  proto::LinkMessage step;
  std::vector<std::uint8_t> bridge;
};

inline std::vector<NodeFrame> NodeFramesAt(std::uint64_t tick) {
  std::vector<NodeFrame> frames;
  if (tick % 4 != 0) return frames;
  const auto sequence = std::uint8_t(tick / 4);
  frames.push_back(PackSampleFrame(tactile_bus::kReferenceNodeId, {40, 65500, 200}, sequence, 0));
  for (std::uint8_t node = 1; node <= tactile_bus::kTactileNodeCount; ++node) {
    const auto z = std::uint16_t(tick > 300 ? 9000 + 100 * node : 8000);
    frames.push_back(PackSampleFrame(node, {std::uint16_t(300 + node), 65000, z}, sequence,
                                     node == 3 ? tactile_bus::kSampleSaturated : 0));
  }
  return frames;
}

inline std::array<float, 6> ImuAt(std::uint64_t tick) {
  const float t = 0.001f * float(tick);
  return {0.01f * t, -0.02f, 0.003f, 0.1f * t, 0.f, 9.81f + 0.01f * t};
}

inline TickInputs InputsAt(std::uint64_t tick) {
  TickInputs in;
  proto::SerialStep* step = in.step.mutable_serial_step();
  step->set_tick(tick);
  if (tick % 7 == 3) step->set_now_offset_ns(-1234);
  proto::SerialImu* imu = step->add_inputs()->mutable_imu();
  for (const float value : ImuAt(tick)) imu->add_gyro_accel(value);
  imu->set_time_offset_ns(-200'000);
  if (tick % 10 == 0) {
    proto::SerialVio* vio = step->add_inputs()->mutable_vio();
    vio->set_capture_offset_ns(-15'000'000);
    for (const float value : {0.01f, -0.02f, 1.f - 0.0001f * float(tick)})
      vio->add_position_m(value);
    for (const float value : {0.99995f, 0.01f, 0.f, 0.f}) vio->add_orientation_wxyz(value);
  }
  if (tick == 0 || tick == 30) {
    proto::SerialSetpoint* setpoint = step->add_inputs()->mutable_setpoint();
    if (tick == 0) {
      for (const float value : {0.f, 0.f, 1.f}) setpoint->add_position_m(value);
      setpoint->set_yaw_rad(0.1f);
      setpoint->set_grasp_regulate(false);
    } else {
      setpoint->set_grasp_regulate(true);
      setpoint->set_grasp_force_n(0.6f);
      setpoint->set_grasp_reference_angle_rad(0.8f);
    }
  }
  for (const NodeFrame& frame : NodeFramesAt(tick)) {
    std::array<std::uint8_t, kUartMaxFrameBytes> bytes{};
    const std::size_t size = EncodeUartFrame(frame, bytes);
    in.bridge.insert(in.bridge.end(), bytes.begin(), bytes.begin() + std::ptrdiff_t(size));
  }
  step->set_bridge_bytes(std::uint32_t(in.bridge.size()));
  return in;
}

// The same ticks fed to a DutCore directly, as the session should.
template <typename S>
class DirectDut {
 public:
  explicit DirectDut(const DutCoreParams<S>& params) : core_(params) {}

  DutCoreOutput<S> Step(std::uint64_t tick) {
    const std::int64_t now_ns = std::int64_t(tick) * kPeriodNs + (tick % 7 == 3 ? -1234 : 0);
    const std::array<float, 6> imu = ImuAt(tick);
    core_.OnImu(Vec3<S>(imu[0], imu[1], imu[2]), Vec3<S>(imu[3], imu[4], imu[5]), now_ns - 200'000);
    if (tick % 10 == 0) {
      core_.OnVio(Vec3<S>(0.01f, -0.02f, 1.f - 0.0001f * float(tick)),
                  Quat<S>(0.99995f, 0.01f, 0.f, 0.f), now_ns - 15'000'000);
    }
    if (tick == 0) {
      reference_.position_m = Vec3<S>(0, 0, 1);
      reference_.yaw_rad = S(0.1f);
      core_.OnSetpoint(reference_, grasp_);
    }
    if (tick == 30) {
      grasp_ = {GraspMode::kForce, S(0.6f), S(0.8f)};
      core_.OnSetpoint(reference_, grasp_);
    }
    for (const NodeFrame& frame : NodeFramesAt(tick)) {
      const NodeSample sample = *UnpackSampleFrame(frame);
      core_.OnSensorSample(sample.node_id, sample.code, sample.sequence,
                           sample.status == tactile_bus::kSampleSaturated, now_ns);
    }
    return core_.Step(now_ns, S(kPeriodS));
  }

 private:
  DutCore<S> core_;
  Reference<S> reference_;
  GraspCommand<S> grasp_;
};

template <typename S>
void ExpectCommandIs(const proto::SerialCommand& command, const DutCoreOutput<S>& out,
                     std::uint64_t tick) {
  EXPECT_EQ(command.answers_tick(), tick);
  ASSERT_EQ(command.rotor_thrust_n_size(), 4);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(command.rotor_thrust_n(i), float(out.rotor_thrust_n[i]));
  EXPECT_EQ(command.armed(), out.armed);
  EXPECT_EQ(command.servo_angle_rad(), float(out.servo_angle_rad));
  ASSERT_EQ(command.estimated_position_m_size(), 3);
  ASSERT_EQ(command.external_force_world_n_size(), 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(command.estimated_position_m(i), float(out.estimated_position_m[i]));
    EXPECT_EQ(command.external_force_world_n(i), float(out.external_force_world_n[i]));
  }
  EXPECT_EQ(command.tactile_ready(), out.tactile_ready);
  EXPECT_EQ(command.grasp_force_estimate_n(), float(out.grasp_force_estimate_n));
  if (command.tactile_force_sensor_n_size() == 0) {
    for (const auto& pad : out.tactile_force_sensor_n) EXPECT_TRUE(pad.isZero());
  } else {
    ASSERT_EQ(command.tactile_force_sensor_n_size(), 18);
    for (int i = 0; i < 18; ++i) {
      EXPECT_EQ(command.tactile_force_sensor_n(i), float(out.tactile_force_sensor_n[i / 3][i % 3]));
    }
  }
}

// Six pads with the firmware bench's numbers: a tactile DUT without a calibration run.
inline host::DutFirmware SixPadFirmware() {
  host::DutFirmware firmware;
  firmware.flight = DefaultFlightControllerParams<double>(0.556);
  firmware.tactile = SixPadTactile<double>(5);
  return firmware;
}

// What a DUT built for S takes from `firmware` over the link.
template <typename S>
DutCoreParams<S> OverTheLink(const host::DutFirmware& firmware) {
  const std::string bytes = host::ToDutConfig(firmware, kPeriodS).SerializeAsString();
  DutConfigOnTarget<S> decoded;
  EXPECT_EQ(
      DecodeDutConfig(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
                      decoded),
      ConfigRefusal::kNone);
  return decoded.params;
}

}  // namespace hilrig::dut_fw
