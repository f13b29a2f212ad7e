#include "host/replay/traffic_wire.h"

#include "dut_link/wire_codec.h"
#include "proto/hil_link.pb.h"
#include "rig/tactile_protocol.h"

namespace hilrig::host {
namespace {

using dut_link::wire::Writer;

// Scalars go through Writer::NonZeroVarint and NonZeroDouble: a field at its default is left out,
// as protobuf's serializer and the link's codec do (in balloon_grasp a sixth of the traffic's
// bytes, most of them a setpoint's zero velocity and acceleration). The wall times have explicit
// presence and are written whenever they are set.

void PutVector(Writer& w, std::uint32_t field, const Eigen::Vector3d& value) {
  const Writer::Nested nested = w.BeginMessage(field);
  w.NonZeroDouble(proto::Vector3::kXFieldNumber, value.x());
  w.NonZeroDouble(proto::Vector3::kYFieldNumber, value.y());
  w.NonZeroDouble(proto::Vector3::kZFieldNumber, value.z());
  w.EndMessage(nested);
}

void PutHeader(Writer& w, const LinkStamp& stamp) {
  const Writer::Nested nested = w.BeginMessage(1);  // every payload's header is its field 1
  w.NonZeroVarint(proto::LinkHeader::kProtocolVersionFieldNumber, kHilLinkProtocolVersion);
  w.NonZeroVarint(proto::LinkHeader::kSequenceFieldNumber, stamp.sequence);
  w.NonZeroVarint(proto::LinkHeader::kTimeNsFieldNumber, static_cast<std::uint64_t>(stamp.time_ns));
  w.EndMessage(nested);
}

void Put(Writer& w, const ImuMessage& m) {
  using P = proto::ImuSample;
  PutHeader(w, m.stamp);
  PutVector(w, P::kGyroRadSFieldNumber, m.gyro_rad_s);
  PutVector(w, P::kAccelMS2FieldNumber, m.accel_m_s2);
  w.NonZeroVarint(P::kGyroClippedFieldNumber, m.gyro_clipped);
  w.NonZeroVarint(P::kAccelClippedFieldNumber, m.accel_clipped);
}

void Put(Writer& w, const VioMessage& m) {
  using P = proto::VioPose;
  PutHeader(w, m.stamp);
  w.NonZeroVarint(P::kCaptureTimeNsFieldNumber, static_cast<std::uint64_t>(m.capture_time_ns));
  PutVector(w, P::kPositionMFieldNumber, m.position_m);
  const Writer::Nested q = w.BeginMessage(P::kOrientationFieldNumber);
  w.NonZeroDouble(proto::Quaternion::kWFieldNumber, m.orientation.w());
  w.NonZeroDouble(proto::Quaternion::kXFieldNumber, m.orientation.x());
  w.NonZeroDouble(proto::Quaternion::kYFieldNumber, m.orientation.y());
  w.NonZeroDouble(proto::Quaternion::kZFieldNumber, m.orientation.z());
  w.EndMessage(q);
}

void Put(Writer& w, const SetpointMessage& m) {
  using P = proto::PositionSetpoint;
  PutHeader(w, m.stamp);
  PutVector(w, P::kPositionMFieldNumber, m.position_m);
  PutVector(w, P::kVelocityMSFieldNumber, m.velocity_m_s);
  PutVector(w, P::kAccelerationMS2FieldNumber, m.acceleration_m_s2);
  w.NonZeroDouble(P::kYawRadFieldNumber, m.yaw_rad);
  w.NonZeroVarint(P::kGraspRegulateFieldNumber, m.grasp_regulate);
  w.NonZeroDouble(P::kGraspForceNFieldNumber, m.grasp_force_n);
  w.NonZeroDouble(P::kGraspReferenceAngleRadFieldNumber, m.grasp_reference_angle_rad);
}

void Put(Writer& w, const MagnetometerMessage& m) {
  PutHeader(w, m.stamp);
  PutVector(w, proto::MagnetometerSample::kFieldBodyTFieldNumber, m.field_body_t);
}

void Put(Writer& w, const BarometerMessage& m) {
  using P = proto::BarometerSample;
  PutHeader(w, m.stamp);
  w.NonZeroDouble(P::kPressurePaFieldNumber, m.pressure_pa);
  w.NonZeroDouble(P::kTemperatureCFieldNumber, m.temperature_c);
}

void Put(Writer& w, const GnssMessage& m) {
  using P = proto::GnssFix;
  PutHeader(w, m.stamp);
  w.NonZeroDouble(P::kLatitudeDegFieldNumber, m.latitude_deg);
  w.NonZeroDouble(P::kLongitudeDegFieldNumber, m.longitude_deg);
  w.NonZeroDouble(P::kAltitudeMFieldNumber, m.altitude_m);
  PutVector(w, P::kVelocityMSFieldNumber, m.velocity_m_s);
  w.NonZeroDouble(P::kHorizontalAccuracyMFieldNumber, m.horizontal_accuracy_m);
  w.NonZeroDouble(P::kVerticalAccuracyMFieldNumber, m.vertical_accuracy_m);
  w.NonZeroVarint(P::kSatellitesFieldNumber, m.satellites);
}

void PutCommand(Writer& w, const ActuatorMessage& m) {
  using P = proto::ActuatorCommand;
  PutHeader(w, m.stamp);
  w.NonZeroVarint(P::kAnswersSequenceFieldNumber, m.answers_sequence);
  w.PackedDoubles(P::kRotorThrustNFieldNumber, m.rotor_thrust_n);
  w.NonZeroVarint(P::kArmedFieldNumber, m.armed);
  PutVector(w, P::kEstimatedPositionMFieldNumber, m.estimated_position_m);
  for (const Eigen::Vector3d& force_n : m.tactile_force_sensor_n) {
    PutVector(w, P::kTactileForceSensorNFieldNumber, force_n);
  }
  w.NonZeroVarint(P::kTactileReadyFieldNumber, m.tactile_ready);
  w.NonZeroDouble(P::kServoAngleRadFieldNumber, m.servo_angle_rad);
  w.NonZeroDouble(P::kGraspForceEstimateNFieldNumber, m.grasp_force_estimate_n);
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
  w.NonZeroVarint(proto::DutStepRequest::kTickFieldNumber, tick);
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
  w.NonZeroVarint(proto::DutCommand::kTickFieldNumber, tick);
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
  w.NonZeroVarint(P::kIdFieldNumber, frame.id);
  w.NonZeroVarint(P::kExtendedFieldNumber, frame.extended);
  w.NonZeroVarint(P::kRemoteFieldNumber, frame.remote);
  w.NonZeroVarint(P::kFdFieldNumber, frame.fd);
  w.NonZeroVarint(P::kBitrateSwitchFieldNumber, frame.bitrate_switch);
  w.NonZeroVarint(P::kErrorStateIndicatorFieldNumber, frame.error_state_indicator);
  w.NonZeroVarint(P::kErrorFieldNumber, frame.error);
  w.NonZeroVarint(P::kLengthFieldNumber, frame.length);
  w.Bytes(P::kDataFieldNumber, frame.payload());
  const rig::TactileFrameKind kind = rig::Classify(frame);
  const std::uint8_t node = rig::TactileNodeOf(frame, kind).value_or(0);
  rig::Result<rig::TactileSample> sample = rig::MakeError("not a sample");
  if (kind == rig::TactileFrameKind::kSample) sample = rig::DecodeTactileSample(frame);
  const bool malformed = kind == rig::TactileFrameKind::kSample && !sample;
  w.NonZeroVarint(P::kKindFieldNumber,
                  malformed ? proto::TACTILE_FRAME_MALFORMED : TactileFrameKindOf(kind));
  w.NonZeroVarint(P::kNodeIdFieldNumber, node);
  if (sample) {
    w.PackedVarints<std::uint16_t>(P::kFieldCodeFieldNumber, sample.value().code);
    w.NonZeroVarint(P::kSampleSequenceFieldNumber, sample.value().sequence);
    w.NonZeroVarint(P::kSampleStatusFieldNumber, sample.value().status);
  }
  return w.written();
}

}  // namespace hilrig::host
