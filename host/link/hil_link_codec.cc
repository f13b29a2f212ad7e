#include "host/link/hil_link_codec.h"

#include <algorithm>

namespace hilrig::host {
namespace {

constexpr std::size_t kMaxVarintBytes = 10;

void PutVector(const Eigen::Vector3d& in, proto::Vector3* out) {
  out->set_x(in.x());
  out->set_y(in.y());
  out->set_z(in.z());
}

Eigen::Vector3d GetVector(const proto::Vector3& in) { return {in.x(), in.y(), in.z()}; }

void PutStamp(const LinkStamp& stamp, proto::LinkHeader* header) {
  header->set_protocol_version(kHilLinkProtocolVersion);
  header->set_sequence(stamp.sequence);
  header->set_time_ns(stamp.time_ns);
}

LinkStamp GetStamp(const proto::LinkHeader& header) {
  return {header.sequence(), header.time_ns()};
}

std::size_t PayloadIndex(const proto::LinkMessage& message) {
  return static_cast<std::size_t>(message.payload_case());
}

// The DutInput alternatives, one by one.
void Fill(const ImuMessage& message, proto::LinkMessage& link) {
  proto::ImuSample* imu = link.mutable_imu();
  PutStamp(message.stamp, imu->mutable_header());
  PutVector(message.gyro_rad_s, imu->mutable_gyro_rad_s());
  PutVector(message.accel_m_s2, imu->mutable_accel_m_s2());
  imu->set_gyro_clipped(message.gyro_clipped);
  imu->set_accel_clipped(message.accel_clipped);
}

void Fill(const VioMessage& message, proto::LinkMessage& link) {
  proto::VioPose* vio = link.mutable_vio();
  PutStamp(message.stamp, vio->mutable_header());
  vio->set_capture_time_ns(message.capture_time_ns);
  PutVector(message.position_m, vio->mutable_position_m());
  proto::Quaternion* q = vio->mutable_orientation();
  q->set_w(message.orientation.w());
  q->set_x(message.orientation.x());
  q->set_y(message.orientation.y());
  q->set_z(message.orientation.z());
}

void Fill(const SetpointMessage& message, proto::LinkMessage& link) {
  proto::PositionSetpoint* setpoint = link.mutable_setpoint();
  PutStamp(message.stamp, setpoint->mutable_header());
  PutVector(message.position_m, setpoint->mutable_position_m());
  PutVector(message.velocity_m_s, setpoint->mutable_velocity_m_s());
  PutVector(message.acceleration_m_s2, setpoint->mutable_acceleration_m_s2());
  setpoint->set_yaw_rad(message.yaw_rad);
  setpoint->set_grasp_regulate(message.grasp_regulate);
  setpoint->set_grasp_force_n(message.grasp_force_n);
  setpoint->set_grasp_reference_angle_rad(message.grasp_reference_angle_rad);
}

void Fill(const MagnetometerMessage& message, proto::LinkMessage& link) {
  proto::MagnetometerSample* mag = link.mutable_mag();
  PutStamp(message.stamp, mag->mutable_header());
  PutVector(message.field_body_t, mag->mutable_field_body_t());
}

void Fill(const BarometerMessage& message, proto::LinkMessage& link) {
  proto::BarometerSample* baro = link.mutable_baro();
  PutStamp(message.stamp, baro->mutable_header());
  baro->set_pressure_pa(message.pressure_pa);
  baro->set_temperature_c(message.temperature_c);
}

void Fill(const GnssMessage& message, proto::LinkMessage& link) {
  proto::GnssFix* gnss = link.mutable_gnss();
  PutStamp(message.stamp, gnss->mutable_header());
  gnss->set_latitude_deg(message.latitude_deg);
  gnss->set_longitude_deg(message.longitude_deg);
  gnss->set_altitude_m(message.altitude_m);
  PutVector(message.velocity_m_s, gnss->mutable_velocity_m_s());
  gnss->set_horizontal_accuracy_m(message.horizontal_accuracy_m);
  gnss->set_vertical_accuracy_m(message.vertical_accuracy_m);
  gnss->set_satellites(message.satellites);
}

ImuMessage FromLink(const proto::ImuSample& message) {
  return {GetStamp(message.header()), GetVector(message.gyro_rad_s()),
          GetVector(message.accel_m_s2()), message.gyro_clipped(), message.accel_clipped()};
}

VioMessage FromLink(const proto::VioPose& message) {
  const proto::Quaternion& q = message.orientation();
  // An absent orientation reads as all zeros; the estimator rejects a zero quaternion itself.
  return {GetStamp(message.header()), message.capture_time_ns(), GetVector(message.position_m()),
          Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z())};
}

SetpointMessage FromLink(const proto::PositionSetpoint& message) {
  return {GetStamp(message.header()),
          GetVector(message.position_m()),
          GetVector(message.velocity_m_s()),
          GetVector(message.acceleration_m_s2()),
          message.yaw_rad(),
          message.grasp_regulate(),
          message.grasp_force_n(),
          message.grasp_reference_angle_rad()};
}

MagnetometerMessage FromLink(const proto::MagnetometerSample& message) {
  return {GetStamp(message.header()), GetVector(message.field_body_t())};
}

BarometerMessage FromLink(const proto::BarometerSample& message) {
  return {GetStamp(message.header()), message.pressure_pa(), message.temperature_c()};
}

GnssMessage FromLink(const proto::GnssFix& message) {
  return {GetStamp(message.header()),
          message.latitude_deg(),
          message.longitude_deg(),
          message.altitude_m(),
          GetVector(message.velocity_m_s()),
          message.horizontal_accuracy_m(),
          message.vertical_accuracy_m(),
          static_cast<std::uint8_t>(std::min<std::uint32_t>(message.satellites(), 255))};
}

// Where each DutInput alternative sits on the link: its payload in a LinkMessage, and the field
// of ActuatorCommand that says how far the DUT had taken its stream. One specialisation per
// alternative; a DutInput alternative without one does not compile.
template <typename Message>
struct LinkStream;

template <>
struct LinkStream<ImuMessage> {
  static constexpr auto kPayload = proto::LinkMessage::kImu;
  static const proto::ImuSample& Payload(const proto::LinkMessage& link) { return link.imu(); }
  static bool HasTaken(const proto::ActuatorCommand& c) { return c.has_last_imu_sequence(); }
  static std::uint64_t Taken(const proto::ActuatorCommand& c) { return c.last_imu_sequence(); }
  static void SetTaken(proto::ActuatorCommand& c, std::uint64_t s) { c.set_last_imu_sequence(s); }
};

template <>
struct LinkStream<VioMessage> {
  static constexpr auto kPayload = proto::LinkMessage::kVio;
  static const proto::VioPose& Payload(const proto::LinkMessage& link) { return link.vio(); }
  static bool HasTaken(const proto::ActuatorCommand& c) { return c.has_last_vio_sequence(); }
  static std::uint64_t Taken(const proto::ActuatorCommand& c) { return c.last_vio_sequence(); }
  static void SetTaken(proto::ActuatorCommand& c, std::uint64_t s) { c.set_last_vio_sequence(s); }
};

template <>
struct LinkStream<SetpointMessage> {
  static constexpr auto kPayload = proto::LinkMessage::kSetpoint;
  static const proto::PositionSetpoint& Payload(const proto::LinkMessage& link) {
    return link.setpoint();
  }
  static bool HasTaken(const proto::ActuatorCommand& c) { return c.has_last_setpoint_sequence(); }
  static std::uint64_t Taken(const proto::ActuatorCommand& c) { return c.last_setpoint_sequence(); }
  static void SetTaken(proto::ActuatorCommand& c, std::uint64_t s) {
    c.set_last_setpoint_sequence(s);
  }
};

template <>
struct LinkStream<MagnetometerMessage> {
  static constexpr auto kPayload = proto::LinkMessage::kMag;
  static const proto::MagnetometerSample& Payload(const proto::LinkMessage& link) {
    return link.mag();
  }
  static bool HasTaken(const proto::ActuatorCommand& c) { return c.has_last_mag_sequence(); }
  static std::uint64_t Taken(const proto::ActuatorCommand& c) { return c.last_mag_sequence(); }
  static void SetTaken(proto::ActuatorCommand& c, std::uint64_t s) { c.set_last_mag_sequence(s); }
};

template <>
struct LinkStream<BarometerMessage> {
  static constexpr auto kPayload = proto::LinkMessage::kBaro;
  static const proto::BarometerSample& Payload(const proto::LinkMessage& link) {
    return link.baro();
  }
  static bool HasTaken(const proto::ActuatorCommand& c) { return c.has_last_baro_sequence(); }
  static std::uint64_t Taken(const proto::ActuatorCommand& c) { return c.last_baro_sequence(); }
  static void SetTaken(proto::ActuatorCommand& c, std::uint64_t s) { c.set_last_baro_sequence(s); }
};

template <>
struct LinkStream<GnssMessage> {
  static constexpr auto kPayload = proto::LinkMessage::kGnss;
  static const proto::GnssFix& Payload(const proto::LinkMessage& link) { return link.gnss(); }
  static bool HasTaken(const proto::ActuatorCommand& c) { return c.has_last_gnss_sequence(); }
  static std::uint64_t Taken(const proto::ActuatorCommand& c) { return c.last_gnss_sequence(); }
  static void SetTaken(proto::ActuatorCommand& c, std::uint64_t s) { c.set_last_gnss_sequence(s); }
};

template <std::size_t kIndex>
using StreamAt = LinkStream<std::variant_alternative_t<kIndex, DutInput>>;

// Calls `use` with StreamAt<index> (an empty tag).
template <typename Use>
void WithLinkStream(std::size_t index, Use&& use) {
  [&]<std::size_t... kIndex>(std::index_sequence<kIndex...>) {
    (void)((index == kIndex ? (use(StreamAt<kIndex>{}), true) : false) || ...);
  }
  (std::make_index_sequence<kDutInputStreams>());
}

}  // namespace

const char* LinkErrorName(LinkErrorKind kind) {
  switch (kind) {
    case LinkErrorKind::kOversized:
      return "oversized";
    case LinkErrorKind::kMalformed:
      return "malformed";
    case LinkErrorKind::kBadVersion:
      return "bad_version";
    case LinkErrorKind::kSequenceGap:
      return "sequence_gap";
    case LinkErrorKind::kDuplicate:
      return "duplicate";
    case LinkErrorKind::kOutOfOrder:
      return "out_of_order";
  }
  return "unknown";
}

std::string LinkError::Message() const { return std::string(LinkErrorName(kind)) + ": " + detail; }

rig::Error LinkProtocolError(LinkErrorKind kind, std::string message) {
  rig::Error error = rig::MakeError(rig::ErrorCode::kLinkProtocol, std::move(message));
  error.subcode = static_cast<int>(kind);
  return error;
}

std::optional<LinkErrorKind> LinkErrorKindOf(const rig::Error& error) {
  constexpr int kLastKind = static_cast<int>(LinkErrorKind::kOutOfOrder);
  if (error.code != rig::ErrorCode::kLinkProtocol) return std::nullopt;
  if (error.subcode < 0 || error.subcode > kLastKind) return std::nullopt;
  return static_cast<LinkErrorKind>(error.subcode);
}

std::vector<rig::Metric> LinkCounterMetrics(const LinkCounters& counters,
                                            const std::string& prefix) {
  const auto d = [](std::uint64_t value) { return static_cast<double>(value); };
  return {{prefix + "messages", d(counters.messages)},
          {prefix + "bytes", d(counters.bytes)},
          {prefix + "oversized", d(counters.oversized)},
          {prefix + "malformed", d(counters.malformed)},
          {prefix + "bad_version", d(counters.bad_version)},
          {prefix + "sequence_gaps", d(counters.sequence_gaps)},
          {prefix + "duplicates", d(counters.duplicates)},
          {prefix + "out_of_order", d(counters.out_of_order)}};
}

rig::Result<std::string> EncodeLinkFrame(const proto::LinkMessage& message,
                                         std::size_t max_message_bytes) {
  const std::size_t size = message.ByteSizeLong();
  if (size > max_message_bytes) {
    return rig::MakeError("link message of " + std::to_string(size) + " bytes exceeds the " +
                          std::to_string(max_message_bytes) + "-byte limit");
  }
  std::string frame;
  for (std::size_t value = size; true; value >>= 7) {
    const auto low = static_cast<char>(value & 0x7F);
    if (value < 0x80) {
      frame.push_back(low);
      break;
    }
    frame.push_back(static_cast<char>(low | 0x80));
  }
  const std::size_t prefix = frame.size();
  frame.resize(prefix + size);
  message.SerializeWithCachedSizesToArray(reinterpret_cast<std::uint8_t*>(frame.data() + prefix));
  return frame;
}

const proto::LinkHeader* HeaderOf(const proto::LinkMessage& message) {
  switch (message.payload_case()) {
    case proto::LinkMessage::kImu:
      return &message.imu().header();
    case proto::LinkMessage::kVio:
      return &message.vio().header();
    case proto::LinkMessage::kSetpoint:
      return &message.setpoint().header();
    case proto::LinkMessage::kMag:
      return &message.mag().header();
    case proto::LinkMessage::kBaro:
      return &message.baro().header();
    case proto::LinkMessage::kGnss:
      return &message.gnss().header();
    case proto::LinkMessage::kCommand:
      return &message.command().header();
    case proto::LinkMessage::kHello:
      return &message.hello().header();
    case proto::LinkMessage::kConfig:
      return &message.config().header();
    case proto::LinkMessage::kStep:
      return &message.step().header();
    case proto::LinkMessage::kBye:
      return &message.bye().header();
    case proto::LinkMessage::kTargetInfo:
      return &message.target_info().header();
    case proto::LinkMessage::kSerialStep:  // the tick stamps these: a line has no room for more
    case proto::LinkMessage::kSerialCommand:
    case proto::LinkMessage::PAYLOAD_NOT_SET:
      break;
  }
  return nullptr;
}

proto::LinkHeader* MutableHeaderOf(proto::LinkMessage& message) {
  switch (message.payload_case()) {
    case proto::LinkMessage::kImu:
      return message.mutable_imu()->mutable_header();
    case proto::LinkMessage::kVio:
      return message.mutable_vio()->mutable_header();
    case proto::LinkMessage::kSetpoint:
      return message.mutable_setpoint()->mutable_header();
    case proto::LinkMessage::kMag:
      return message.mutable_mag()->mutable_header();
    case proto::LinkMessage::kBaro:
      return message.mutable_baro()->mutable_header();
    case proto::LinkMessage::kGnss:
      return message.mutable_gnss()->mutable_header();
    case proto::LinkMessage::kCommand:
      return message.mutable_command()->mutable_header();
    case proto::LinkMessage::kHello:
      return message.mutable_hello()->mutable_header();
    case proto::LinkMessage::kConfig:
      return message.mutable_config()->mutable_header();
    case proto::LinkMessage::kStep:
      return message.mutable_step()->mutable_header();
    case proto::LinkMessage::kBye:
      return message.mutable_bye()->mutable_header();
    case proto::LinkMessage::kTargetInfo:
      return message.mutable_target_info()->mutable_header();
    case proto::LinkMessage::kSerialStep:
    case proto::LinkMessage::kSerialCommand:
    case proto::LinkMessage::PAYLOAD_NOT_SET:
      break;
  }
  return nullptr;
}

void LinkSequencer::Stamp(proto::LinkMessage& message, std::int64_t time_ns, bool assign_sequence) {
  proto::LinkHeader* header = MutableHeaderOf(message);
  if (header == nullptr) return;
  header->set_protocol_version(kHilLinkProtocolVersion);
  if (!assign_sequence) return;
  header->set_sequence(next_[PayloadIndex(message)]++);
  header->set_time_ns(time_ns);
}

LinkDecoder::LinkDecoder(std::size_t max_message_bytes) : max_message_bytes_(max_message_bytes) {}

void LinkDecoder::Feed(std::span<const std::uint8_t> bytes) {
  counters_.bytes += bytes.size();
  if (broken_) return;
  // Consumed bytes are dropped lazily, so that a stream of small frames does not shift the
  // buffer on every message.
  if (read_at_ > 0 && read_at_ == buffer_.size()) {
    buffer_.clear();
    read_at_ = 0;
  } else if (read_at_ > 4 * max_message_bytes_) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(read_at_));
    read_at_ = 0;
  }
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

void LinkDecoder::Feed(const std::string& bytes) {
  Feed(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                     bytes.size()));
}

std::optional<LinkEvent> LinkDecoder::Fail(LinkErrorKind kind, std::string detail) {
  switch (kind) {
    case LinkErrorKind::kOversized:
      ++counters_.oversized;
      broken_ = true;
      break;
    case LinkErrorKind::kMalformed:
      ++counters_.malformed;
      broken_ = true;
      break;
    case LinkErrorKind::kBadVersion:
      ++counters_.bad_version;
      break;
    case LinkErrorKind::kSequenceGap:
      ++counters_.sequence_gaps;
      break;
    case LinkErrorKind::kDuplicate:
      ++counters_.duplicates;
      break;
    case LinkErrorKind::kOutOfOrder:
      ++counters_.out_of_order;
      break;
  }
  if (broken_) {
    buffer_.clear();
    read_at_ = 0;
  }
  return LinkError{kind, std::move(detail)};
}

std::optional<LinkEvent> LinkDecoder::Next() {
  if (broken_) return std::nullopt;
  std::uint64_t length = 0;
  std::size_t at = read_at_;
  for (int shift = 0;; shift += 7) {
    if (at == buffer_.size()) return std::nullopt;  // the length prefix is not complete yet
    if (at - read_at_ == kMaxVarintBytes) {
      return Fail(LinkErrorKind::kMalformed, "length prefix longer than 10 bytes");
    }
    const std::uint8_t byte = buffer_[at++];
    if (shift < 64) length |= std::uint64_t{byte & 0x7Fu} << shift;
    if (length > max_message_bytes_ || (shift >= 63 && (byte & 0x7E) != 0)) {
      return Fail(LinkErrorKind::kOversized, "length prefix announces more than " +
                                                 std::to_string(max_message_bytes_) + " bytes");
    }
    if ((byte & 0x80) == 0) break;
  }
  if (buffer_.size() - at < length) return std::nullopt;
  proto::LinkMessage message;
  const bool parsed = message.ParseFromArray(buffer_.data() + at, static_cast<int>(length));
  read_at_ = at + static_cast<std::size_t>(length);
  if (!parsed) return Fail(LinkErrorKind::kMalformed, "bytes do not parse as a LinkMessage");
  return Check(std::move(message));
}

std::optional<LinkEvent> LinkDecoder::Check(proto::LinkMessage message) {
  const proto::LinkHeader* header = HeaderOf(message);
  if (header == nullptr) {
    return Fail(LinkErrorKind::kMalformed, "a LinkMessage without a payload");
  }
  const std::string stream =
      proto::LinkMessage::descriptor()->FindFieldByNumber(message.payload_case())->name();
  if (header->protocol_version() != kHilLinkProtocolVersion) {
    return Fail(LinkErrorKind::kBadVersion, stream + " message of protocol version " +
                                                std::to_string(header->protocol_version()) +
                                                ", this side speaks " +
                                                std::to_string(kHilLinkProtocolVersion));
  }
  std::optional<std::uint64_t>& last = last_[PayloadIndex(message)];
  const std::uint64_t sequence = header->sequence();
  const std::uint64_t expected = last ? *last + 1 : 0;
  const auto describe = [&](const char* what) {
    return stream + " sequence " + std::to_string(sequence) + " " + what + ", expected " +
           std::to_string(expected);
  };
  if (last && sequence == *last) return Fail(LinkErrorKind::kDuplicate, describe("repeated"));
  if (last && sequence < *last) return Fail(LinkErrorKind::kOutOfOrder, describe("arrived late"));
  if (sequence != expected) {
    last = sequence;  // resynchronise, so that one lost message is one error
    return Fail(LinkErrorKind::kSequenceGap, describe("skips ahead"));
  }
  last = sequence;
  ++counters_.messages;
  return LinkEvent(std::move(message));
}

void FillLink(const ActuatorMessage& message, proto::ActuatorCommand& out) {
  proto::ActuatorCommand* command = &out;
  PutStamp(message.stamp, command->mutable_header());
  command->set_answers_sequence(message.answers_sequence);
  command->clear_rotor_thrust_n();
  for (double thrust_n : message.rotor_thrust_n) command->add_rotor_thrust_n(thrust_n);
  command->set_armed(message.armed);
  PutVector(message.estimated_position_m, command->mutable_estimated_position_m());
  command->clear_tactile_force_sensor_n();  // keeps the elements for the next add
  for (const Eigen::Vector3d& force_n : message.tactile_force_sensor_n) {
    PutVector(force_n, command->add_tactile_force_sensor_n());
  }
  command->set_tactile_ready(message.tactile_ready);
  command->set_servo_angle_rad(message.servo_angle_rad);
  command->set_grasp_force_estimate_n(message.grasp_force_estimate_n);
  PutVector(message.external_force_world_n, command->mutable_external_force_world_n());
}

proto::LinkMessage ToLink(const ActuatorMessage& message) {
  proto::LinkMessage link;
  FillLink(message, *link.mutable_command());
  return link;
}

rig::Result<ActuatorMessage> FromLink(const proto::ActuatorCommand& message) {
  ActuatorMessage command;
  if (message.rotor_thrust_n_size() != static_cast<int>(command.rotor_thrust_n.size())) {
    return rig::MakeError("actuator command with " + std::to_string(message.rotor_thrust_n_size()) +
                          " rotor thrusts instead of 4");
  }
  if (message.tactile_force_sensor_n_size() !=
      static_cast<int>(command.tactile_force_sensor_n.size())) {
    return rig::MakeError("actuator command with " +
                          std::to_string(message.tactile_force_sensor_n_size()) +
                          " tactile forces instead of 6");
  }
  command.stamp = GetStamp(message.header());
  command.answers_sequence = message.answers_sequence();
  std::copy(message.rotor_thrust_n().begin(), message.rotor_thrust_n().end(),
            command.rotor_thrust_n.begin());
  command.armed = message.armed();
  command.estimated_position_m = GetVector(message.estimated_position_m());
  for (std::size_t i = 0; i < command.tactile_force_sensor_n.size(); ++i) {
    command.tactile_force_sensor_n[i] =
        GetVector(message.tactile_force_sensor_n(static_cast<int>(i)));
  }
  command.tactile_ready = message.tactile_ready();
  command.servo_angle_rad = message.servo_angle_rad();
  command.grasp_force_estimate_n = message.grasp_force_estimate_n();
  command.external_force_world_n = GetVector(message.external_force_world_n());
  return command;
}

void FillLink(const DutInput& input, proto::LinkMessage& link) {
  VisitDutInput(input, [&link](const auto& message) { Fill(message, link); });
}

proto::LinkMessage ToLink(const DutInput& input) {
  proto::LinkMessage link;
  FillLink(input, link);
  return link;
}

const google::protobuf::FieldDescriptor& DutInputPayloadField(std::size_t input_index) {
  int number = 0;
  WithLinkStream(input_index, [&number](auto stream) { number = decltype(stream)::kPayload; });
  return *proto::LinkMessage::descriptor()->FindFieldByNumber(number);
}

std::optional<DutInput> DutInputFromLink(const proto::LinkMessage& message) {
  std::optional<DutInput> input;
  [&]<std::size_t... kIndex>(std::index_sequence<kIndex...>) {
    (void)((message.payload_case() == StreamAt<kIndex>::kPayload
                ? (input.emplace(std::in_place_index<kIndex>,
                                 FromLink(StreamAt<kIndex>::Payload(message))),
                   true)
                : false) ||
           ...);
  }
  (std::make_index_sequence<kDutInputStreams>());
  return input;
}

std::optional<std::uint64_t> LastTakenSequence(const proto::ActuatorCommand& command,
                                               std::size_t input_index) {
  std::optional<std::uint64_t> sequence;
  WithLinkStream(input_index, [&](auto stream) {
    if (decltype(stream)::HasTaken(command)) sequence = decltype(stream)::Taken(command);
  });
  return sequence;
}

void SetLastTakenSequence(proto::ActuatorCommand& command, std::size_t input_index,
                          std::uint64_t sequence) {
  WithLinkStream(input_index, [&](auto stream) { decltype(stream)::SetTaken(command, sequence); });
}

}  // namespace hilrig::host
