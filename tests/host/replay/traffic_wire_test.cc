// The traffic's hand-written wire bytes parse, with the protobuf library, as the very messages the
// library's own conversion (host/link/hil_link_codec.h) makes: every input stream, the command with
// its packed thrusts and six force vectors, a step with and without its wall time, and CAN frames
// of every tactile kind, a malformed one and a CAN FD one included.
#include "host/replay/traffic_wire.h"

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "host/link/hil_link_codec.h"
#include "proto/hil_link.pb.h"

namespace hilrig::host {
namespace {

using google::protobuf::util::MessageDifferencer;

std::string Bytes(std::span<const std::uint8_t> bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

// One of each stream, every field set to something other than zero.
std::vector<DutInput> EveryInput() {
  ImuMessage imu;
  imu.stamp = {12, 345'000'000};
  imu.gyro_rad_s = {0.1, -0.2, 1.0 / 3};
  imu.accel_m_s2 = {0, -0.0, 9.81};
  imu.accel_clipped = true;
  VioMessage vio;
  vio.stamp = {3, 400'000'000};
  vio.capture_time_ns = 380'000'000;
  vio.position_m = {1, 2, 3};
  vio.orientation = Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5);
  SetpointMessage setpoint;
  setpoint.stamp = {9, 1};
  setpoint.position_m = {0, 0, 0.55};
  setpoint.yaw_rad = -1.5;
  setpoint.grasp_regulate = true;
  setpoint.grasp_force_n = 0.6;
  setpoint.grasp_reference_angle_rad = 0.3;
  MagnetometerMessage mag;
  mag.field_body_t = {2e-5, -4e-6, 4.5e-5};
  BarometerMessage baro;
  baro.pressure_pa = 101325;
  baro.temperature_c = -3.5;
  GnssMessage gnss;
  gnss.latitude_deg = 47.397742;
  gnss.longitude_deg = 8.545594;
  gnss.altitude_m = 488;
  gnss.velocity_m_s = {0.1, 0, -0.2};
  gnss.horizontal_accuracy_m = 0.5;
  gnss.vertical_accuracy_m = 0.8;
  gnss.satellites = 12;
  return {imu, vio, setpoint, mag, baro, gnss};
}

TEST(TrafficWireTest, EveryInputParsesAsTheLinksOwnConversion) {
  TrafficBuffer buffer;
  for (const DutInput& input : EveryInput()) {
    const proto::LinkMessage expected = ToLink(input);
    const google::protobuf::FieldDescriptor& field = DutInputPayloadField(input.index());
    const google::protobuf::Message& expected_payload =
        expected.GetReflection()->GetMessage(expected, &field);
    std::unique_ptr<google::protobuf::Message> parsed(expected_payload.New());
    ASSERT_TRUE(parsed->ParseFromString(Bytes(EncodeDutInput(input, buffer)))) << field.name();
    EXPECT_TRUE(MessageDifferencer::Equals(*parsed, expected_payload))
        << field.name() << ":\n"
        << parsed->DebugString() << "vs\n"
        << expected_payload.DebugString();
    // Fields holding their default (zeros of the inputs above) take no bytes, as protobuf's own.
    EXPECT_EQ(EncodeDutInput(input, buffer).size(), expected_payload.ByteSizeLong())
        << field.name();
  }
}

TEST(TrafficWireTest, ACommandParsesWithItsTickWallTimeAndEveryOutput) {
  ActuatorMessage command;
  command.stamp = {41, 41'000'000};
  command.answers_sequence = 41;
  command.rotor_thrust_n = {1.25, 1.5, -0.0, std::numeric_limits<double>::quiet_NaN()};
  command.armed = true;
  command.estimated_position_m = {0.01, -0.02, 0.5};
  for (int i = 0; i < 6; ++i) command.tactile_force_sensor_n[i] = {0.01 * i, -0.1, 0.05 * i};
  command.tactile_ready = true;
  command.servo_angle_rad = 0.42;
  command.grasp_force_estimate_n = 0.61;
  command.external_force_world_n = {0, 0, -0.15};
  TrafficBuffer buffer;
  proto::DutCommand parsed;
  ASSERT_TRUE(parsed.ParseFromString(Bytes(EncodeDutCommand(41, 123'456, command, buffer))));
  EXPECT_EQ(parsed.tick(), 41u);
  ASSERT_TRUE(parsed.has_wall_time_ns());
  EXPECT_EQ(parsed.wall_time_ns(), 123'456);
  // NaN is not equal to itself: compare through the struct, bit for bit.
  ActuatorMessage back = FromLink(parsed.command()).value();
  EXPECT_TRUE(std::isnan(back.rotor_thrust_n[3]));
  command.rotor_thrust_n[3] = back.rotor_thrust_n[3] = 0;
  EXPECT_EQ(ToLink(back).SerializeAsString(), ToLink(command).SerializeAsString());

  EXPECT_EQ(EncodeDutCommand(41, 123'456, command, buffer).size(), parsed.ByteSizeLong());

  ASSERT_TRUE(parsed.ParseFromString(Bytes(EncodeDutCommand(7, std::nullopt, {}, buffer))));
  EXPECT_EQ(EncodeDutCommand(7, std::nullopt, {}, buffer).size(), parsed.ByteSizeLong());
  EXPECT_FALSE(parsed.has_wall_time_ns());
  EXPECT_EQ(parsed.command().tactile_force_sensor_n_size(), 6);
  EXPECT_EQ(parsed.command().rotor_thrust_n_size(), 4);
}

TEST(TrafficWireTest, AStepCarriesItsWallTimeOnlyWhenItHasOne) {
  TrafficBuffer buffer;
  proto::DutStepRequest step;
  ASSERT_TRUE(step.ParseFromString(Bytes(EncodeStepRequest(1ull << 40, std::nullopt, buffer))));
  EXPECT_EQ(step.tick(), 1ull << 40);
  EXPECT_FALSE(step.has_wall_time_ns());
  ASSERT_TRUE(step.ParseFromString(Bytes(EncodeStepRequest(3, 0, buffer))));
  EXPECT_TRUE(step.has_wall_time_ns());
}

proto::DutCanFrame Parsed(const rig::CanFrame& frame) {
  TrafficBuffer buffer;
  proto::DutCanFrame parsed;
  EXPECT_TRUE(parsed.ParseFromString(Bytes(EncodeDutCanFrame(frame, buffer))));
  return parsed;
}

TEST(TrafficWireTest, ACanFrameKeepsItsBytesAndWhatTheTactileProtocolReadsInIt) {
  rig::TactileSample sample;
  sample.node_id = 3;
  sample.code = {100, 200, 65000};
  sample.sequence = 7;
  sample.status = 1;
  const rig::CanFrame sample_frame = rig::EncodeTactileSample(sample);
  proto::DutCanFrame parsed = Parsed(sample_frame);
  EXPECT_EQ(parsed.kind(), proto::TACTILE_FRAME_SAMPLE);
  EXPECT_EQ(parsed.id(), sample_frame.id);
  EXPECT_EQ(parsed.length(), sample_frame.length);
  EXPECT_EQ(parsed.data(), Bytes(sample_frame.payload()));
  EXPECT_EQ(parsed.node_id(), 3u);
  ASSERT_EQ(parsed.field_code_size(), 3);
  EXPECT_EQ(parsed.field_code(2), 65000u);
  EXPECT_EQ(parsed.sample_sequence(), 7u);
  EXPECT_EQ(parsed.sample_status(), 1u);

  rig::TactileStatus status;
  status.node_id = 7;
  parsed = Parsed(rig::EncodeTactileStatus(status));
  EXPECT_EQ(parsed.kind(), proto::TACTILE_FRAME_STATUS);
  EXPECT_EQ(parsed.node_id(), 7u);
  EXPECT_EQ(parsed.field_code_size(), 0);

  // A sample's id with too few bytes: kept as it came, flagged.
  rig::CanFrame short_sample = sample_frame;
  short_sample.length = 3;
  parsed = Parsed(short_sample);
  EXPECT_EQ(parsed.kind(), proto::TACTILE_FRAME_MALFORMED);
  EXPECT_EQ(parsed.data().size(), 3u);

  std::array<std::uint8_t, 64> payload{};
  payload.fill(0xA5);
  parsed = Parsed(rig::CanFrame::FdExtended(0x1ABCDEF, payload, true));
  EXPECT_EQ(parsed.kind(), proto::TACTILE_FRAME_NOT_CLASSIC_DATA);
  EXPECT_TRUE(parsed.fd());
  EXPECT_TRUE(parsed.bitrate_switch());
  EXPECT_EQ(parsed.data().size(), 64u);
}

}  // namespace
}  // namespace hilrig::host
