#include "host/mavlink/mavlink_messages.h"

#include <algorithm>
#include <bit>
#include <concepts>
#include <utility>

namespace hilrig::mavlink {
namespace {

// Each message's wire fields are listed once, in VisitFields, in wire order with their definition
// names; Pack, Unpack and the descriptors (hence the CRC_EXTRA check) all walk that one list.
// Extensions() marks where the extension fields begin.

template <typename M>
using Bare = std::remove_const_t<M>;

template <typename M, typename V>
requires std::same_as<Bare<M>, Heartbeat>
constexpr void VisitFields(M& m, V& v) {
  v.Field("custom_mode", m.custom_mode);
  v.Field("type", m.type);
  v.Field("autopilot", m.autopilot);
  v.Field("base_mode", m.base_mode);
  v.Field("system_status", m.system_status);
  // The definition types this uint8_t_mavlink_version; it is a uint8_t on the wire and in the
  // CRC_EXTRA rule.
  v.Field("mavlink_version", m.mavlink_version);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, SystemTime>
constexpr void VisitFields(M& m, V& v) {
  v.Field("time_unix_usec", m.time_unix_usec);
  v.Field("time_boot_ms", m.time_boot_ms);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, CommandLong>
constexpr void VisitFields(M& m, V& v) {
  v.Field("param1", m.param1);
  v.Field("param2", m.param2);
  v.Field("param3", m.param3);
  v.Field("param4", m.param4);
  v.Field("param5", m.param5);
  v.Field("param6", m.param6);
  v.Field("param7", m.param7);
  v.Field("command", m.command);
  v.Field("target_system", m.target_system);
  v.Field("target_component", m.target_component);
  v.Field("confirmation", m.confirmation);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, CommandAck>
constexpr void VisitFields(M& m, V& v) {
  v.Field("command", m.command);
  v.Field("result", m.result);
  v.Extensions();
  v.Field("progress", m.progress);
  v.Field("result_param2", m.result_param2);
  v.Field("target_system", m.target_system);
  v.Field("target_component", m.target_component);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, SetPositionTargetLocalNed>
constexpr void VisitFields(M& m, V& v) {
  v.Field("time_boot_ms", m.time_boot_ms);
  v.Field("x", m.x_m);
  v.Field("y", m.y_m);
  v.Field("z", m.z_m);
  v.Field("vx", m.vx_m_s);
  v.Field("vy", m.vy_m_s);
  v.Field("vz", m.vz_m_s);
  v.Field("afx", m.afx_m_s2);
  v.Field("afy", m.afy_m_s2);
  v.Field("afz", m.afz_m_s2);
  v.Field("yaw", m.yaw_rad);
  v.Field("yaw_rate", m.yaw_rate_rad_s);
  v.Field("type_mask", m.type_mask);
  v.Field("target_system", m.target_system);
  v.Field("target_component", m.target_component);
  v.Field("coordinate_frame", m.coordinate_frame);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, HilActuatorControls>
constexpr void VisitFields(M& m, V& v) {
  v.Field("time_usec", m.time_usec);
  v.Field("flags", m.flags);
  v.Field("controls", m.controls);
  v.Field("mode", m.mode);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, VisionPositionEstimate>
constexpr void VisitFields(M& m, V& v) {
  v.Field("usec", m.usec);
  v.Field("x", m.x_m);
  v.Field("y", m.y_m);
  v.Field("z", m.z_m);
  v.Field("roll", m.roll_rad);
  v.Field("pitch", m.pitch_rad);
  v.Field("yaw", m.yaw_rad);
  v.Extensions();
  v.Field("covariance", m.covariance);
  v.Field("reset_counter", m.reset_counter);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, HilSensor>
constexpr void VisitFields(M& m, V& v) {
  v.Field("time_usec", m.time_usec);
  v.Field("xacc", m.xacc_m_s2);
  v.Field("yacc", m.yacc_m_s2);
  v.Field("zacc", m.zacc_m_s2);
  v.Field("xgyro", m.xgyro_rad_s);
  v.Field("ygyro", m.ygyro_rad_s);
  v.Field("zgyro", m.zgyro_rad_s);
  v.Field("xmag", m.xmag_gauss);
  v.Field("ymag", m.ymag_gauss);
  v.Field("zmag", m.zmag_gauss);
  v.Field("abs_pressure", m.abs_pressure_hpa);
  v.Field("diff_pressure", m.diff_pressure_hpa);
  v.Field("pressure_alt", m.pressure_alt);
  v.Field("temperature", m.temperature_degc);
  v.Field("fields_updated", m.fields_updated);
  v.Extensions();
  v.Field("id", m.id);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, Timesync>
constexpr void VisitFields(M& m, V& v) {
  v.Field("tc1", m.tc1_ns);
  v.Field("ts1", m.ts1_ns);
  v.Extensions();
  v.Field("target_system", m.target_system);
  v.Field("target_component", m.target_component);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, HilGps>
constexpr void VisitFields(M& m, V& v) {
  v.Field("time_usec", m.time_usec);
  v.Field("lat", m.lat_deg_e7);
  v.Field("lon", m.lon_deg_e7);
  v.Field("alt", m.alt_mm);
  v.Field("eph", m.eph);
  v.Field("epv", m.epv);
  v.Field("vel", m.vel_cm_s);
  v.Field("vn", m.vn_cm_s);
  v.Field("ve", m.ve_cm_s);
  v.Field("vd", m.vd_cm_s);
  v.Field("cog", m.cog_cdeg);
  v.Field("fix_type", m.fix_type);
  v.Field("satellites_visible", m.satellites_visible);
  v.Extensions();
  v.Field("id", m.id);
  v.Field("yaw", m.yaw_cdeg);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, Odometry>
constexpr void VisitFields(M& m, V& v) {
  v.Field("time_usec", m.time_usec);
  v.Field("x", m.x_m);
  v.Field("y", m.y_m);
  v.Field("z", m.z_m);
  v.Field("q", m.q);
  v.Field("vx", m.vx_m_s);
  v.Field("vy", m.vy_m_s);
  v.Field("vz", m.vz_m_s);
  v.Field("rollspeed", m.rollspeed_rad_s);
  v.Field("pitchspeed", m.pitchspeed_rad_s);
  v.Field("yawspeed", m.yawspeed_rad_s);
  v.Field("pose_covariance", m.pose_covariance);
  v.Field("velocity_covariance", m.velocity_covariance);
  v.Field("frame_id", m.frame_id);
  v.Field("child_frame_id", m.child_frame_id);
  v.Extensions();
  v.Field("reset_counter", m.reset_counter);
  v.Field("estimator_type", m.estimator_type);
  v.Field("quality", m.quality_percent);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, DebugFloatArray>
constexpr void VisitFields(M& m, V& v) {
  v.Field("time_usec", m.time_usec);
  v.Field("array_id", m.array_id);
  v.Field("name", m.name);
  v.Extensions();
  v.Field("data", m.data);
}

template <typename M, typename V>
requires std::same_as<Bare<M>, CanFrame>
constexpr void VisitFields(M& m, V& v) {
  v.Field("id", m.id);
  v.Field("target_system", m.target_system);
  v.Field("target_component", m.target_component);
  v.Field("bus", m.bus);
  v.Field("len", m.len);
  v.Field("data", m.data);
}

// The definition's name of each C++ type a field can have.
template <typename T>
constexpr std::string_view WireTypeName() {
  if constexpr (std::is_same_v<T, char>) return "char";
  if constexpr (std::is_same_v<T, std::uint8_t>) return "uint8_t";
  if constexpr (std::is_same_v<T, std::int8_t>) return "int8_t";
  if constexpr (std::is_same_v<T, std::uint16_t>) return "uint16_t";
  if constexpr (std::is_same_v<T, std::int16_t>) return "int16_t";
  if constexpr (std::is_same_v<T, std::uint32_t>) return "uint32_t";
  if constexpr (std::is_same_v<T, std::int32_t>) return "int32_t";
  if constexpr (std::is_same_v<T, std::uint64_t>) return "uint64_t";
  if constexpr (std::is_same_v<T, std::int64_t>) return "int64_t";
  if constexpr (std::is_same_v<T, float>) return "float";
  if constexpr (std::is_same_v<T, double>) return "double";
  return {};
}

template <typename T>
concept WireScalar = !WireTypeName<T>().empty();

// Enough for the message with the most fields (ODOMETRY, 18).
constexpr std::size_t kMaxFields = 24;

// Records the fields a VisitFields walk presents, with their offsets.
struct Describer {
  std::array<FieldInfo, kMaxFields> fields{};
  std::size_t count = 0;
  std::size_t offset = 0;
  std::size_t base_bytes = 0;
  bool in_extensions = false;

  template <WireScalar T>
  constexpr void Field(std::string_view name, const T&) {
    Add(WireTypeName<T>(), name, 0, sizeof(T));
  }
  template <WireScalar T, std::size_t N>
  constexpr void Field(std::string_view name, const std::array<T, N>&) {
    static_assert(N > 0 && N < 256);
    Add(WireTypeName<T>(), name, static_cast<std::uint8_t>(N), sizeof(T));
  }
  constexpr void Extensions() {
    in_extensions = true;
    base_bytes = offset;
  }
  constexpr void Add(std::string_view type, std::string_view name, std::uint8_t array_length,
                     std::size_t element_bytes) {
    fields[count++] = {type,
                       name,
                       array_length,
                       static_cast<std::uint8_t>(element_bytes),
                       static_cast<std::uint8_t>(offset),
                       in_extensions};
    offset += element_bytes * (array_length == 0 ? 1 : array_length);
    if (!in_extensions) base_bytes = offset;
  }
};

template <KnownMessage M>
constexpr Describer Describe() {
  M message{};
  Describer describer;
  VisitFields(message, describer);
  return describer;
}

template <KnownMessage M>
constexpr auto FieldTable() {
  constexpr Describer described = Describe<M>();
  std::array<FieldInfo, described.count> table{};
  std::copy_n(described.fields.begin(), described.count, table.begin());
  return table;
}

template <KnownMessage M>
constexpr std::array kFields = FieldTable<M>();

// The layout VisitFields produces must be the published one: lengths, wire order (base fields by
// non-increasing element size) and CRC_EXTRA.
template <KnownMessage M>
constexpr bool LayoutMatchesPublished() {
  constexpr Describer d = Describe<M>();
  if (d.base_bytes != M::kBasePayloadBytes || d.offset != M::kFullPayloadBytes) return false;
  for (std::size_t i = 1; i < d.count; ++i) {
    const FieldInfo& a = d.fields[i - 1];
    const FieldInfo& b = d.fields[i];
    if (!b.extension && b.element_bytes > a.element_bytes) return false;
    if (a.extension && !b.extension) return false;
  }
  return CrcExtraFromFields(M::kName, kFields<M>) == M::kCrcExtra;
}

template <typename Variant>
struct AllLayoutsMatch;
template <typename... Ms>
struct AllLayoutsMatch<std::variant<Ms...>>
    : std::bool_constant<(LayoutMatchesPublished<Ms>() && ...)> {};
static_assert(AllLayoutsMatch<AnyMessage>::value);

template <typename T>
constexpr auto AsUnsigned(T value) {
  if constexpr (sizeof(T) == 1) return std::bit_cast<std::uint8_t>(value);
  if constexpr (sizeof(T) == 2) return std::bit_cast<std::uint16_t>(value);
  if constexpr (sizeof(T) == 4) return std::bit_cast<std::uint32_t>(value);
  if constexpr (sizeof(T) == 8) return std::bit_cast<std::uint64_t>(value);
}

class PayloadWriter {
 public:
  explicit PayloadWriter(std::span<std::uint8_t> out) : out_(out) {}

  template <WireScalar T>
  void Field(std::string_view, const T& value) {
    Put(value);
  }
  template <WireScalar T, std::size_t N>
  void Field(std::string_view, const std::array<T, N>& values) {
    for (const T& value : values) Put(value);
  }
  void Extensions() {}

 private:
  template <typename T>
  void Put(T value) {
    auto bits = AsUnsigned(value);
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      out_[pos_++] = static_cast<std::uint8_t>(bits & 0xFF);
      if constexpr (sizeof(T) > 1) bits = static_cast<decltype(bits)>(bits >> 8);
    }
  }

  std::span<std::uint8_t> out_;
  std::size_t pos_ = 0;
};

class PayloadReader {
 public:
  explicit PayloadReader(std::span<const std::uint8_t> in) : in_(in) {}

  template <WireScalar T>
  void Field(std::string_view, T& value) {
    value = Get<T>();
  }
  template <WireScalar T, std::size_t N>
  void Field(std::string_view, std::array<T, N>& values) {
    for (T& value : values) value = Get<T>();
  }
  void Extensions() {}

 private:
  template <typename T>
  T Get() {
    using U = decltype(AsUnsigned(T{}));
    U bits = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i, ++pos_) {
      const U byte = pos_ < in_.size() ? in_[pos_] : 0;
      bits = static_cast<U>(bits | static_cast<U>(byte << (8 * i)));
    }
    return std::bit_cast<T>(bits);
  }

  std::span<const std::uint8_t> in_;
  std::size_t pos_ = 0;
};

template <KnownMessage M>
constexpr MessageInfo InfoOf() {
  return {M::kId,
          M::kName,
          M::kCrcExtra,
          static_cast<std::uint8_t>(M::kBasePayloadBytes),
          static_cast<std::uint8_t>(M::kFullPayloadBytes),
          kFields<M>};
}

template <typename Variant>
struct InfoTable;
template <typename... Ms>
struct InfoTable<std::variant<Ms...>> {
  static constexpr std::array<MessageInfo, sizeof...(Ms)> kInfos{InfoOf<Ms>()...};
};

constexpr const auto& kMessages = InfoTable<AnyMessage>::kInfos;

constexpr bool IdsAscendAndAreUnique() {
  for (std::size_t i = 1; i < kMessages.size(); ++i) {
    if (kMessages[i - 1].id >= kMessages[i].id) return false;
  }
  return true;
}
static_assert(IdsAscendAndAreUnique(), "AnyMessage lists the messages in id order");

template <KnownMessage M>
std::optional<AnyMessage> DecodeAs(const Frame& frame) {
  if (frame.payload_length > M::kFullPayloadBytes) return std::nullopt;
  return Unpack<M>(std::span<const std::uint8_t>(frame.payload.data(), frame.payload_length));
}

template <typename Variant>
struct Decoders;
template <typename... Ms>
struct Decoders<std::variant<Ms...>> {
  static std::optional<AnyMessage> Decode(const Frame& frame) {
    std::optional<AnyMessage> result;
    ((frame.message_id == Ms::kId ? (void)(result = DecodeAs<Ms>(frame)) : void()), ...);
    return result;
  }
};

}  // namespace

template <KnownMessage M>
void Pack(const M& message, std::span<std::uint8_t, M::kFullPayloadBytes> payload) {
  PayloadWriter writer(payload);
  VisitFields(message, writer);
}

template <KnownMessage M>
M Unpack(std::span<const std::uint8_t> full_payload) {
  M message{};
  PayloadReader reader(full_payload);
  VisitFields(message, reader);
  return message;
}

#define HILRIG_MAVLINK_INSTANTIATE(M)                                             \
  template void Pack<M>(const M&, std::span<std::uint8_t, M::kFullPayloadBytes>); \
  template M Unpack<M>(std::span<const std::uint8_t>);
HILRIG_MAVLINK_INSTANTIATE(Heartbeat)
HILRIG_MAVLINK_INSTANTIATE(SystemTime)
HILRIG_MAVLINK_INSTANTIATE(CommandLong)
HILRIG_MAVLINK_INSTANTIATE(CommandAck)
HILRIG_MAVLINK_INSTANTIATE(SetPositionTargetLocalNed)
HILRIG_MAVLINK_INSTANTIATE(HilActuatorControls)
HILRIG_MAVLINK_INSTANTIATE(VisionPositionEstimate)
HILRIG_MAVLINK_INSTANTIATE(HilSensor)
HILRIG_MAVLINK_INSTANTIATE(Timesync)
HILRIG_MAVLINK_INSTANTIATE(HilGps)
HILRIG_MAVLINK_INSTANTIATE(Odometry)
HILRIG_MAVLINK_INSTANTIATE(DebugFloatArray)
HILRIG_MAVLINK_INSTANTIATE(CanFrame)
#undef HILRIG_MAVLINK_INSTANTIATE

std::span<const MessageInfo> AllMessages() { return kMessages; }

const MessageInfo* FindMessage(std::uint32_t id) {
  for (const MessageInfo& info : kMessages) {
    if (info.id == id) return &info;
  }
  return nullptr;
}

std::optional<WireInfo> FindWireInfo(std::uint32_t id) {
  const MessageInfo* info = FindMessage(id);
  if (info == nullptr) return std::nullopt;
  return WireInfo{info->crc_extra, info->full_payload_bytes};
}

std::uint32_t MessageId(const AnyMessage& message) {
  return std::visit([](const auto& m) { return std::remove_cvref_t<decltype(m)>::kId; }, message);
}

std::size_t EncodeMessage(const AnyMessage& message, std::uint8_t sequence, std::uint8_t system_id,
                          std::uint8_t component_id, std::span<std::uint8_t> out) {
  return std::visit(
      [&](const auto& m) -> std::size_t {
        using M = std::remove_cvref_t<decltype(m)>;
        Frame frame;
        frame.sequence = sequence;
        frame.system_id = system_id;
        frame.component_id = component_id;
        frame.message_id = M::kId;
        frame.payload_length = static_cast<std::uint8_t>(M::kFullPayloadBytes);
        Pack(m, std::span<std::uint8_t, M::kFullPayloadBytes>(frame.payload.data(),
                                                              M::kFullPayloadBytes));
        return EncodeFrame(frame, M::kCrcExtra, out);
      },
      message);
}

std::optional<AnyMessage> DecodeMessage(const Frame& frame) {
  return Decoders<AnyMessage>::Decode(frame);
}

}  // namespace hilrig::mavlink
