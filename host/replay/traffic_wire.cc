#include "host/replay/traffic_wire.h"

#include <bit>

#include "dut_link/wire_codec.h"
#include "proto/hil_link.pb.h"
#include "rig/tactile_protocol.h"

namespace hilrig::host {
namespace {

using dut_link::wire::Writer;

// Like protobuf's serializer and the link's codec, a proto3 field holding its default is left
// out (in balloon_grasp a sixth of the traffic's bytes, most of them a setpoint's zero velocity
// and acceleration). A double is left out only when all its bits are zero (-0.0 is written, as
// protobuf does).
void PutDouble(Writer& w, std::uint32_t field, double value) {
  if (std::bit_cast<std::uint64_t>(value) != 0) w.Double(field, value);
}

void PutVarint(Writer& w, std::uint32_t field, std::uint64_t value) {
  if (value != 0) w.Varint(field, value);
}

void PutBool(Writer& w, std::uint32_t field, bool value) {
  if (value) w.Bool(field, true);
}

void PutVector(Writer& w, std::uint32_t field, const Eigen::Vector3d& value) {
  const Writer::Nested nested = w.BeginMessage(field);
  PutDouble(w, proto::Vector3::kXFieldNumber, value.x());
  PutDouble(w, proto::Vector3::kYFieldNumber, value.y());
  PutDouble(w, proto::Vector3::kZFieldNumber, value.z());
  w.EndMessage(nested);
}

void PutHeader(Writer& w, const LinkStamp& stamp) {
  const Writer::Nested nested = w.BeginMessage(1);  // every payload's header is its field 1
  PutVarint(w, proto::LinkHeader::kProtocolVersionFieldNumber, kHilLinkProtocolVersion);
  PutVarint(w, proto::LinkHeader::kSequenceFieldNumber, stamp.sequence);
  PutVarint(w, proto::LinkHeader::kTimeNsFieldNumber, static_cast<std::uint64_t>(stamp.time_ns));
  w.EndMessage(nested);
}

void Put(Writer& w, const ImuMessage& m) {
  using P = proto::ImuSample;
  PutHeader(w, m.stamp);
  PutVector(w, P::kGyroRadSFieldNumber, m.gyro_rad_s);
  PutVector(w, P::kAccelMS2FieldNumber, m.accel_m_s2);
  PutBool(w, P::kGyroClippedFieldNumber, m.gyro_clipped);
  PutBool(w, P::kAccelClippedFieldNumber, m.accel_clipped);
}

void Put(Writer& w, const VioMessage& m) {
  using P = proto::VioPose;
  PutHeader(w, m.stamp);
  PutVarint(w, P::kCaptureTimeNsFieldNumber, static_cast<std::uint64_t>(m.capture_time_ns));
  PutVector(w, P::kPositionMFieldNumber, m.position_m);
  const Writer::Nested q = w.BeginMessage(P::kOrientationFieldNumber);
  PutDouble(w, proto::Quaternion::kWFieldNumber, m.orientation.w());
  PutDouble(w, proto::Quaternion::kXFieldNumber, m.orientation.x());
  PutDouble(w, proto::Quaternion::kYFieldNumber, m.orientation.y());
  PutDouble(w, proto::Quaternion::kZFieldNumber, m.orientation.z());
  w.EndMessage(q);
}

void Put(Writer& w, const SetpointMessage& m) {
  using P = proto::PositionSetpoint;
  PutHeader(w, m.stamp);
  PutVector(w, P::kPositionMFieldNumber, m.position_m);
  PutVector(w, P::kVelocityMSFieldNumber, m.velocity_m_s);
  PutVector(w, P::kAccelerationMS2FieldNumber, m.acceleration_m_s2);
  PutDouble(w, P::kYawRadFieldNumber, m.yaw_rad);
  PutBool(w, P::kGraspRegulateFieldNumber, m.grasp_regulate);
  PutDouble(w, P::kGraspForceNFieldNumber, m.grasp_force_n);
  PutDouble(w, P::kGraspReferenceAngleRadFieldNumber, m.grasp_reference_angle_rad);
}

void Put(Writer& w, const MagnetometerMessage& m) {
  PutHeader(w, m.stamp);
  PutVector(w, proto::MagnetometerSample::kFieldBodyTFieldNumber, m.field_body_t);
}

void Put(Writer& w, const BarometerMessage& m) {
  using P = proto::BarometerSample;
  PutHeader(w, m.stamp);
  PutDouble(w, P::kPressurePaFieldNumber, m.pressure_pa);
  PutDouble(w, P::kTemperatureCFieldNumber, m.temperature_c);
}

void Put(Writer& w, const GnssMessage& m) {
  using P = proto::GnssFix;
  PutHeader(w, m.stamp);
  PutDouble(w, P::kLatitudeDegFieldNumber, m.latitude_deg);
  PutDouble(w, P::kLongitudeDegFieldNumber, m.longitude_deg);
  PutDouble(w, P::kAltitudeMFieldNumber, m.altitude_m);
  PutVector(w, P::kVelocityMSFieldNumber, m.velocity_m_s);
  PutDouble(w, P::kHorizontalAccuracyMFieldNumber, m.horizontal_accuracy_m);
  PutDouble(w, P::kVerticalAccuracyMFieldNumber, m.vertical_accuracy_m);
  PutVarint(w, P::kSatellitesFieldNumber, m.satellites);
}

void PutCommand(Writer& w, const ActuatorMessage& m) {
  using P = proto::ActuatorCommand;
  PutHeader(w, m.stamp);
  PutVarint(w, P::kAnswersSequenceFieldNumber, m.answers_sequence);
  w.PackedDoubles(P::kRotorThrustNFieldNumber, m.rotor_thrust_n);
  PutBool(w, P::kArmedFieldNumber, m.armed);
  PutVector(w, P::kEstimatedPositionMFieldNumber, m.estimated_position_m);
  for (const Eigen::Vector3d& force_n : m.tactile_force_sensor_n) {
    PutVector(w, P::kTactileForceSensorNFieldNumber, force_n);
  }
  PutBool(w, P::kTactileReadyFieldNumber, m.tactile_ready);
  PutDouble(w, P::kServoAngleRadFieldNumber, m.servo_angle_rad);
  PutDouble(w, P::kGraspForceEstimateNFieldNumber, m.grasp_force_estimate_n);
  PutVector(w, P::kExternalForceWorldNFieldNumber, m.external_force_world_n);
}

}  // namespace

proto::TactileFrameKind TactileFrameKindOf(rig::TactileFrameKind kind) {
  switch (kind) {
    case rig::TactileFrameKind::kSample:
      return proto::TACTILE_FRAME_SAMPLE;
    case rig::TactileFrameKind::kStatus:
      return proto::TACTILE_FRAME_STATUS;
    case rig::TactileFrameKind::kConfig:
      return proto::TACTILE_FRAME_CONFIG;
    case rig::TactileFrameKind::kUnknownId:
      return proto::TACTILE_FRAME_UNKNOWN_ID;
    case rig::TactileFrameKind::kNotClassicData:
      return proto::TACTILE_FRAME_NOT_CLASSIC_DATA;
  }
  return proto::TACTILE_FRAME_KIND_UNSPECIFIED;
}

std::span<const std::uint8_t> EncodeDutInput(const DutInput& input, TrafficBuffer& buffer) {
  Writer w(buffer);
  VisitDutInput(input, [&w](const auto& message) { Put(w, message); });
  return w.written();
}

std::span<const std::uint8_t> EncodeStepRequest(std::uint64_t tick,
                                                std::optional<std::int64_t> wall_ns,
                                                TrafficBuffer& buffer) {
  Writer w(buffer);
  PutVarint(w, proto::DutStepRequest::kTickFieldNumber, tick);
  if (wall_ns) {
    w.Varint(proto::DutStepRequest::kWallTimeNsFieldNumber, static_cast<std::uint64_t>(*wall_ns));
  }
  return w.written();
}

std::span<const std::uint8_t> EncodeDutCommand(std::uint64_t tick,
                                               std::optional<std::int64_t> wall_ns,
                                               const ActuatorMessage& command,
                                               TrafficBuffer& buffer) {
  Writer w(buffer);
  PutVarint(w, proto::DutCommand::kTickFieldNumber, tick);
  if (wall_ns) {
    w.Varint(proto::DutCommand::kWallTimeNsFieldNumber, static_cast<std::uint64_t>(*wall_ns));
  }
  const Writer::Nested nested = w.BeginMessage(proto::DutCommand::kCommandFieldNumber);
  PutCommand(w, command);
  w.EndMessage(nested);
  return w.written();
}

std::span<const std::uint8_t> EncodeDutCanFrame(const rig::CanFrame& frame, TrafficBuffer& buffer) {
  using P = proto::DutCanFrame;
  Writer w(buffer);
  PutVarint(w, P::kIdFieldNumber, frame.id);
  PutBool(w, P::kExtendedFieldNumber, frame.extended);
  PutBool(w, P::kRemoteFieldNumber, frame.remote);
  PutBool(w, P::kFdFieldNumber, frame.fd);
  PutBool(w, P::kBitrateSwitchFieldNumber, frame.bitrate_switch);
  PutBool(w, P::kErrorStateIndicatorFieldNumber, frame.error_state_indicator);
  PutBool(w, P::kErrorFieldNumber, frame.error);
  PutVarint(w, P::kLengthFieldNumber, frame.length);
  w.Bytes(P::kDataFieldNumber, frame.payload());
  const rig::TactileFrameKind kind = rig::Classify(frame);
  const std::uint8_t node = rig::TactileNodeOf(frame, kind).value_or(0);
  rig::Result<rig::TactileSample> sample = rig::MakeError("not a sample");
  if (kind == rig::TactileFrameKind::kSample) sample = rig::DecodeTactileSample(frame);
  const bool malformed = kind == rig::TactileFrameKind::kSample && !sample;
  PutVarint(w, P::kKindFieldNumber,
            malformed ? proto::TACTILE_FRAME_MALFORMED : TactileFrameKindOf(kind));
  PutVarint(w, P::kNodeIdFieldNumber, node);
  if (sample) {
    w.PackedVarints<std::uint16_t>(P::kFieldCodeFieldNumber, sample.value().code);
    PutVarint(w, P::kSampleSequenceFieldNumber, sample.value().sequence);
    PutVarint(w, P::kSampleStatusFieldNumber, sample.value().status);
  }
  return w.written();
}

}  // namespace hilrig::host
