#include "host/report/run_log.h"

#include <cmath>
#include <numbers>

#include "host/mcap/protobuf_channel.h"
#include "proto/foxglove/FrameTransform.pb.h"
#include "proto/foxglove/PosesInFrame.pb.h"
#include "proto/run_log.pb.h"

namespace hilrig::host {
namespace {

// The rig's Vector3 and Foxglove's, the same three fields.
template <typename Vector3>
void Set(Vector3& out, const Eigen::Vector3d& value) {
  out.set_x(value.x());
  out.set_y(value.y());
  out.set_z(value.z());
}

void Set(foxglove::Quaternion& out, const Eigen::Quaterniond& value) {
  out.set_x(value.x());
  out.set_y(value.y());
  out.set_z(value.z());
  out.set_w(value.w());
}

// Foxglove orders a frame's transforms by this stamp, not by the record's log time: the same.
void Set(google::protobuf::Timestamp& out, std::int64_t log_time_ns) {
  out.set_seconds(log_time_ns / 1'000'000'000);
  out.set_nanos(static_cast<std::int32_t>(log_time_ns % 1'000'000'000));
}

std::int64_t LogTimeNs(double time_s) {
  return kRunLogEpochNs + static_cast<std::int64_t>(std::llround(time_s * 1e9));
}

foxglove::FrameTransform BodyTransformOf(const TraceSample& s, std::int64_t log_time_ns) {
  foxglove::FrameTransform transform;
  Set(*transform.mutable_timestamp(), log_time_ns);
  transform.set_parent_frame_id(kRunLogWorldFrame);
  transform.set_child_frame_id(kRunLogBodyFrame);
  Set(*transform.mutable_translation(), s.position_m);
  Set(*transform.mutable_rotation(),
      QuaternionOfRollPitchYaw(s.roll_pitch_yaw_deg * (std::numbers::pi / 180.0)));
  return transform;
}

proto::VehicleTruth VehicleOf(const TraceSample& s) {
  proto::VehicleTruth vehicle;
  Set(*vehicle.mutable_position_m(), s.position_m);
  Set(*vehicle.mutable_velocity_m_s(), s.velocity_m_s);
  Set(*vehicle.mutable_roll_pitch_yaw_deg(), s.roll_pitch_yaw_deg);
  vehicle.set_tilt_deg(s.tilt_deg);
  for (double thrust_n : s.rotor_thrust_n) vehicle.add_rotor_thrust_n(thrust_n);
  vehicle.set_ground_force_n(s.ground_force_n);
  Set(*vehicle.mutable_reference_m(), s.reference_m);
  Set(*vehicle.mutable_position_error_m(), s.position_m - s.reference_m);
  return vehicle;
}

proto::DutEstimates EstimatesOf(const TraceSample& s) {
  proto::DutEstimates estimates;
  Set(*estimates.mutable_estimated_position_m(), s.estimated_position_m);
  estimates.set_grasp_force_estimate_n(s.grasp_force_estimate_n);
  estimates.set_load_estimate_n(s.load_estimate_n);
  estimates.set_servo_command_rad(s.servo_command_rad);
  return estimates;
}

proto::GraspTruth GraspOf(const TraceSample& s) {
  proto::GraspTruth grasp;
  grasp.set_grasp_force_n(s.grasp_force_n);
  grasp.set_grasp_force_setpoint_n(s.grasp_force_setpoint_n);
  grasp.set_load_n(s.load_n);
  grasp.set_object_mass_kg(s.object_mass_kg);
  grasp.set_servo_angle_rad(s.servo_angle_rad);
  grasp.set_object_held(s.object_held);
  grasp.set_object_dropped(s.object_dropped);
  grasp.set_object_damaged(s.object_damaged);
  grasp.set_slip_speed_m_s(s.slip_speed_m_s);
  return grasp;
}

proto::PadForces PadsOf(const std::array<double, kTracePadCount>& forces_n) {
  proto::PadForces pads;
  for (double force_n : forces_n) pads.add_force_n(force_n);
  return pads;
}

// Chunks are compressed and written on the thread that writes the messages: a run writes its log
// from a thread of the log's own (host/replay/background_run_log.h), and a third busy thread on
// a two-core machine took turns with the run's loop (balloon_grasp's loop +34 % with the chunks
// compressed on a thread of the writer's own, +13 % without: docs/performance.md, P31). zstd's
// faster mode: level -1 compresses 1.4 times faster than level 1 for a file 3 % larger.
mcap::McapWriterOptions LogWriterOptions() {
  mcap::McapWriterOptions options;
  options.zstd_level = -1;
  return options;
}

}  // namespace

Eigen::Quaterniond QuaternionOfRollPitchYaw(const Eigen::Vector3d& roll_pitch_yaw_rad) {
  return Eigen::AngleAxisd(roll_pitch_yaw_rad.z(), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(roll_pitch_yaw_rad.y(), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll_pitch_yaw_rad.x(), Eigen::Vector3d::UnitX());
}

RunLogWriter::RunLogWriter(std::ostream& out, RunLogScene scene)
    : writer_(out, LogWriterOptions()), scene_(std::move(scene)) {}

rig::Result<std::unique_ptr<RunLogWriter>> RunLogWriter::Open(std::ostream& out,
                                                              RunLogScene scene) {
  std::unique_ptr<RunLogWriter> log(new RunLogWriter(out, std::move(scene)));
  if (auto opened = log->writer_.Open("", "hilrig"); !opened) return opened.error();
  struct Wanted {
    bool wanted;
    const google::protobuf::Descriptor* message;
    const char* topic;
    std::uint16_t* id;
  };
  Channels& ids = log->channels_;
  const bool grasp = log->scene_.grasp, pads = log->scene_.pads;
  for (const Wanted& channel :
       {Wanted{true, proto::VehicleTruth::descriptor(), "/plant/vehicle", &ids.vehicle},
        Wanted{true, proto::DutEstimates::descriptor(), "/dut/estimates", &ids.estimates},
        Wanted{grasp, proto::GraspTruth::descriptor(), "/plant/grasp", &ids.grasp},
        Wanted{pads, proto::PadForces::descriptor(), "/plant/pads", &ids.plant_pads},
        Wanted{pads, proto::PadForces::descriptor(), "/dut/pads", &ids.dut_pads},
        Wanted{true, proto::TimelineMark::descriptor(), "/run/events", &ids.events},
        Wanted{true, foxglove::FrameTransform::descriptor(), "/tf", &ids.tf},
        Wanted{!log->scene_.reference_path.empty(), foxglove::PosesInFrame::descriptor(),
               "/plant/reference_path", &ids.reference_path}}) {
    if (!channel.wanted) continue;
    auto added = log->AddChannel(*channel.message, channel.topic);
    if (!added) return added.error();
    *channel.id = added.value();
  }
  for (const EnvelopeSpec& envelope : log->scene_.envelopes) {
    auto added = log->AddChannel(*proto::EnvelopeSample::descriptor(), "/checks/" + envelope.name);
    if (!added) return added.error();
    log->envelopes_.push_back({EnvelopeCheck(envelope), EnvelopeProgress{}, added.value()});
  }
  log->WriteReferencePath();
  return log;
}

rig::Result<std::uint16_t> RunLogWriter::AddChannel(const google::protobuf::Descriptor& message,
                                                    std::string_view topic) {
  auto schema = schemas_.find(&message);
  if (schema == schemas_.end()) {
    auto added = mcap::AddProtobufSchema(writer_, message);
    if (!added) {
      if (!failure_) failure_ = added.error();
      return added.error();
    }
    schema = schemas_.emplace(&message, added.value()).first;
  }
  auto channel = writer_.AddChannel(schema->second, topic, mcap::kProtobufEncoding);
  if (!channel && !failure_) failure_ = channel.error();
  return channel;
}

void RunLogWriter::Log(std::uint16_t channel, std::int64_t time_ns,
                       const google::protobuf::MessageLite& message,
                       std::optional<std::int64_t> publish_time_ns) {
  WriteMessage(channel, kRunLogEpochNs + time_ns, message,
               kRunLogEpochNs + publish_time_ns.value_or(time_ns));
}

void RunLogWriter::LogBytes(std::uint16_t channel, std::int64_t time_ns,
                            std::span<const std::uint8_t> payload,
                            std::optional<std::int64_t> publish_time_ns) {
  Write(channel, kRunLogEpochNs + time_ns,
        std::string_view(reinterpret_cast<const char*>(payload.data()), payload.size()),
        kRunLogEpochNs + publish_time_ns.value_or(time_ns));
}

void RunLogWriter::WriteMessage(std::uint16_t channel, std::int64_t log_time_ns,
                                const google::protobuf::MessageLite& message,
                                std::int64_t publish_time_ns) {
  if (failure_) return;  // the run's log is lost already: no serializing for nothing
  message.SerializeToString(&payload_);
  Write(channel, log_time_ns, payload_, publish_time_ns);
}

void RunLogWriter::Write(std::uint16_t channel, std::int64_t log_time_ns, std::string_view payload,
                         std::int64_t publish_time_ns) {
  if (failure_) return;
  mcap::MessageToWrite message;
  message.channel_id = channel;
  message.sequence = sequence_++;
  message.log_time_ns = static_cast<std::uint64_t>(log_time_ns);
  message.publish_time_ns = static_cast<std::uint64_t>(publish_time_ns);
  message.payload = payload;
  if (auto written = writer_.Write(message); !written) failure_ = written.error();
}

void RunLogWriter::WriteEventsUpTo(double time_s) {
  for (; next_event_ < scene_.events.size() && scene_.events[next_event_].time_s <= time_s;
       ++next_event_) {
    proto::TimelineMark mark;
    mark.set_label(scene_.events[next_event_].label);
    WriteMessage(channels_.events, LogTimeNs(scene_.events[next_event_].time_s), mark);
  }
}

// The whole path in one message at time 0: Foxglove draws it from then on, as the run's backdrop.
void RunLogWriter::WriteReferencePath() {
  if (scene_.reference_path.empty()) return;
  foxglove::PosesInFrame path;
  Set(*path.mutable_timestamp(), kRunLogEpochNs);
  path.set_frame_id(kRunLogWorldFrame);
  for (const ReferencePose& reference : scene_.reference_path) {
    foxglove::Pose& pose = *path.add_poses();
    Set(*pose.mutable_position(), reference.position_m);
    Set(*pose.mutable_orientation(),
        Eigen::Quaterniond(Eigen::AngleAxisd(reference.yaw_rad, Eigen::Vector3d::UnitZ())));
  }
  WriteMessage(channels_.reference_path, kRunLogEpochNs, path);
}

void RunLogWriter::WriteEnvelopes(const TraceSample& sample, std::int64_t log_time_ns) {
  for (LoggedEnvelope& envelope : envelopes_) {
    const EnvelopeReading reading = envelope.check.Read(sample, envelope.progress);
    proto::EnvelopeSample logged;
    logged.set_active(reading.checked);
    if (reading.checked) {
      logged.set_value(reading.value);
      logged.set_margin(reading.margin);
    }
    const EnvelopeSpec& spec = envelope.check.spec();
    if (spec.lower) logged.set_lower(*spec.lower);
    if (spec.upper) logged.set_upper(*spec.upper);
    logged.set_violated(reading.violation());
    WriteMessage(envelope.channel, log_time_ns, logged);
  }
}

void RunLogWriter::Add(const TraceSample& sample) {
  WriteEventsUpTo(sample.time_s);
  const std::int64_t time_ns = LogTimeNs(sample.time_s);
  WriteMessage(channels_.vehicle, time_ns, VehicleOf(sample));
  WriteMessage(channels_.estimates, time_ns, EstimatesOf(sample));
  if (scene_.grasp) WriteMessage(channels_.grasp, time_ns, GraspOf(sample));
  if (scene_.pads) {
    WriteMessage(channels_.plant_pads, time_ns, PadsOf(sample.pad_force_n));
    WriteMessage(channels_.dut_pads, time_ns, PadsOf(sample.pad_force_estimate_n));
  }
  WriteMessage(channels_.tf, time_ns, BodyTransformOf(sample, time_ns));
  WriteEnvelopes(sample, time_ns);
}

// Events after the last sample never happened in the run (it stopped first): they stay out.
rig::Result<void> RunLogWriter::Close() {
  if (failure_) return *failure_;
  return writer_.Close();
}

}  // namespace hilrig::host
