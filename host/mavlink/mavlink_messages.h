// The MAVLink common-set messages a HIL rig exchanges with a flight stack (heartbeat, time,
// commands, HIL sensor/GPS input and actuator output, time sync, vision and odometry, a debug
// array, forwarded CAN frames) as plain structs, with units in member names where the message
// definition gives units, and their exact wire layout: little-endian, base fields sorted by type
// size (largest first, stable), array fields sorted by their element size, extension fields after
// the base ones in definition order. Each message has a descriptor listing its wire fields as the
// definition names them, from which its CRC_EXTRA is recomputed (CrcExtraFromFields), so a wrong
// field order, type or name shows as a CRC_EXTRA that differs from the published one. EncodeMessage
// and DecodeMessage join the structs to the framing of host/mavlink/mavlink_frame.h. Nothing here
// allocates or throws.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <type_traits>
#include <variant>

#include "host/mavlink/mavlink_frame.h"

namespace hilrig::mavlink {

// Members are declared in wire order. MAV_* names are the definition's enums, carried as integers.

struct Heartbeat {
  static constexpr std::uint32_t kId = 0;
  static constexpr std::string_view kName = "HEARTBEAT";
  static constexpr std::uint8_t kCrcExtra = 50;
  static constexpr std::size_t kBasePayloadBytes = 9;
  static constexpr std::size_t kFullPayloadBytes = 9;

  std::uint32_t custom_mode = 0;
  std::uint8_t type = 0;           // MAV_TYPE
  std::uint8_t autopilot = 0;      // MAV_AUTOPILOT
  std::uint8_t base_mode = 0;      // MAV_MODE_FLAG bits
  std::uint8_t system_status = 0;  // MAV_STATE
  // The protocol version a sender speaks; MAVLink 2 senders put 3 here.
  std::uint8_t mavlink_version = 3;

  bool operator==(const Heartbeat&) const = default;
};

struct SystemTime {
  static constexpr std::uint32_t kId = 2;
  static constexpr std::string_view kName = "SYSTEM_TIME";
  static constexpr std::uint8_t kCrcExtra = 137;
  static constexpr std::size_t kBasePayloadBytes = 12;
  static constexpr std::size_t kFullPayloadBytes = 12;

  std::uint64_t time_unix_usec = 0;
  std::uint32_t time_boot_ms = 0;

  bool operator==(const SystemTime&) const = default;
};

struct CommandLong {
  static constexpr std::uint32_t kId = 76;
  static constexpr std::string_view kName = "COMMAND_LONG";
  static constexpr std::uint8_t kCrcExtra = 152;
  static constexpr std::size_t kBasePayloadBytes = 33;
  static constexpr std::size_t kFullPayloadBytes = 33;

  // Units depend on the command.
  float param1 = 0;
  float param2 = 0;
  float param3 = 0;
  float param4 = 0;
  float param5 = 0;
  float param6 = 0;
  float param7 = 0;
  std::uint16_t command = 0;  // MAV_CMD
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint8_t confirmation = 0;

  bool operator==(const CommandLong&) const = default;
};

struct CommandAck {
  static constexpr std::uint32_t kId = 77;
  static constexpr std::string_view kName = "COMMAND_ACK";
  static constexpr std::uint8_t kCrcExtra = 143;
  static constexpr std::size_t kBasePayloadBytes = 3;
  static constexpr std::size_t kFullPayloadBytes = 10;

  std::uint16_t command = 0;  // MAV_CMD
  std::uint8_t result = 0;    // MAV_RESULT
  // Extensions.
  std::uint8_t progress = 0;  // percentage while in progress (UINT8_MAX: unknown), or a reason
  std::int32_t result_param2 = 0;
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;

  bool operator==(const CommandAck&) const = default;
};

struct SetPositionTargetLocalNed {
  static constexpr std::uint32_t kId = 84;
  static constexpr std::string_view kName = "SET_POSITION_TARGET_LOCAL_NED";
  static constexpr std::uint8_t kCrcExtra = 143;
  static constexpr std::size_t kBasePayloadBytes = 53;
  static constexpr std::size_t kFullPayloadBytes = 53;

  std::uint32_t time_boot_ms = 0;
  float x_m = 0;
  float y_m = 0;
  float z_m = 0;
  float vx_m_s = 0;
  float vy_m_s = 0;
  float vz_m_s = 0;
  // Acceleration, or force in N when type_mask says so.
  float afx_m_s2 = 0;
  float afy_m_s2 = 0;
  float afz_m_s2 = 0;
  float yaw_rad = 0;
  float yaw_rate_rad_s = 0;
  std::uint16_t type_mask = 0;  // POSITION_TARGET_TYPEMASK bits: dimensions to ignore
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint8_t coordinate_frame = 0;  // MAV_FRAME

  bool operator==(const SetPositionTargetLocalNed&) const = default;
};

struct HilActuatorControls {
  static constexpr std::uint32_t kId = 93;
  static constexpr std::string_view kName = "HIL_ACTUATOR_CONTROLS";
  static constexpr std::uint8_t kCrcExtra = 47;
  static constexpr std::size_t kBasePayloadBytes = 81;
  static constexpr std::size_t kFullPayloadBytes = 81;

  std::uint64_t time_usec = 0;
  std::uint64_t flags = 0;           // bit 0: the simulation runs in lockstep
  std::array<float, 16> controls{};  // normalised outputs, -1 .. 1
  std::uint8_t mode = 0;             // MAV_MODE_FLAG bits, arming included

  bool operator==(const HilActuatorControls&) const = default;
};

struct VisionPositionEstimate {
  static constexpr std::uint32_t kId = 102;
  static constexpr std::string_view kName = "VISION_POSITION_ESTIMATE";
  static constexpr std::uint8_t kCrcExtra = 158;
  static constexpr std::size_t kBasePayloadBytes = 32;
  static constexpr std::size_t kFullPayloadBytes = 117;

  std::uint64_t usec = 0;
  float x_m = 0;
  float y_m = 0;
  float z_m = 0;
  float roll_rad = 0;
  float pitch_rad = 0;
  float yaw_rad = 0;
  // Extensions.
  // Upper-right triangle of the 6x6 pose covariance, row-major; NaN first element: unknown.
  std::array<float, 21> covariance{};
  std::uint8_t reset_counter = 0;

  bool operator==(const VisionPositionEstimate&) const = default;
};

struct HilSensor {
  static constexpr std::uint32_t kId = 107;
  static constexpr std::string_view kName = "HIL_SENSOR";
  static constexpr std::uint8_t kCrcExtra = 108;
  static constexpr std::size_t kBasePayloadBytes = 64;
  static constexpr std::size_t kFullPayloadBytes = 65;

  std::uint64_t time_usec = 0;
  float xacc_m_s2 = 0;
  float yacc_m_s2 = 0;
  float zacc_m_s2 = 0;
  float xgyro_rad_s = 0;
  float ygyro_rad_s = 0;
  float zgyro_rad_s = 0;
  float xmag_gauss = 0;
  float ymag_gauss = 0;
  float zmag_gauss = 0;
  float abs_pressure_hpa = 0;
  float diff_pressure_hpa = 0;
  // Altitude computed from pressure; the definition gives it no unit.
  float pressure_alt = 0;
  float temperature_degc = 0;
  std::uint32_t fields_updated = 0;  // HIL_SENSOR_UPDATED_FLAGS bits
  // Extensions.
  std::uint8_t id = 0;  // sensor instance, zero-based

  bool operator==(const HilSensor&) const = default;
};

struct Timesync {
  static constexpr std::uint32_t kId = 111;
  static constexpr std::string_view kName = "TIMESYNC";
  static constexpr std::uint8_t kCrcExtra = 34;
  static constexpr std::size_t kBasePayloadBytes = 16;
  static constexpr std::size_t kFullPayloadBytes = 18;

  std::int64_t tc1_ns = 0;  // 0 in a request; the responder's time in a response
  std::int64_t ts1_ns = 0;  // the requester's time, mirrored in the response
  // Extensions.
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;

  bool operator==(const Timesync&) const = default;
};

struct HilGps {
  static constexpr std::uint32_t kId = 113;
  static constexpr std::string_view kName = "HIL_GPS";
  static constexpr std::uint8_t kCrcExtra = 124;
  static constexpr std::size_t kBasePayloadBytes = 36;
  static constexpr std::size_t kFullPayloadBytes = 39;

  std::uint64_t time_usec = 0;
  std::int32_t lat_deg_e7 = 0;
  std::int32_t lon_deg_e7 = 0;
  std::int32_t alt_mm = 0;  // MSL, positive up
  std::uint16_t eph = 0;    // HDOP x 100; UINT16_MAX: unknown
  std::uint16_t epv = 0;    // VDOP x 100; UINT16_MAX: unknown
  std::uint16_t vel_cm_s = 0;
  std::int16_t vn_cm_s = 0;
  std::int16_t ve_cm_s = 0;
  std::int16_t vd_cm_s = 0;
  std::uint16_t cog_cdeg = 0;
  std::uint8_t fix_type = 0;  // 0-1: no fix, 2: 2D, 3: 3D
  std::uint8_t satellites_visible = 0;
  // Extensions.
  std::uint8_t id = 0;         // receiver instance, zero-based
  std::uint16_t yaw_cdeg = 0;  // 0: not available; north is 36000

  bool operator==(const HilGps&) const = default;
};

struct Odometry {
  static constexpr std::uint32_t kId = 331;
  static constexpr std::string_view kName = "ODOMETRY";
  static constexpr std::uint8_t kCrcExtra = 91;
  static constexpr std::size_t kBasePayloadBytes = 230;
  static constexpr std::size_t kFullPayloadBytes = 233;

  std::uint64_t time_usec = 0;
  float x_m = 0;
  float y_m = 0;
  float z_m = 0;
  std::array<float, 4> q{};  // w, x, y, z
  float vx_m_s = 0;
  float vy_m_s = 0;
  float vz_m_s = 0;
  float rollspeed_rad_s = 0;
  float pitchspeed_rad_s = 0;
  float yawspeed_rad_s = 0;
  // Upper-right triangles of the 6x6 covariances, row-major; NaN first element: unknown.
  std::array<float, 21> pose_covariance{};
  std::array<float, 21> velocity_covariance{};
  std::uint8_t frame_id = 0;        // MAV_FRAME of the pose
  std::uint8_t child_frame_id = 0;  // MAV_FRAME of the twist
  // Extensions.
  std::uint8_t reset_counter = 0;
  std::uint8_t estimator_type = 0;  // MAV_ESTIMATOR_TYPE
  std::int8_t quality_percent = 0;  // -1: failed, 0: unknown, 100: best

  bool operator==(const Odometry&) const = default;
};

struct DebugFloatArray {
  static constexpr std::uint32_t kId = 350;
  static constexpr std::string_view kName = "DEBUG_FLOAT_ARRAY";
  static constexpr std::uint8_t kCrcExtra = 232;
  static constexpr std::size_t kBasePayloadBytes = 20;
  static constexpr std::size_t kFullPayloadBytes = 252;

  std::uint64_t time_usec = 0;
  std::uint16_t array_id = 0;
  std::array<char, 10> name{};  // NUL-padded, not NUL-terminated when all 10 are used
  // Extensions.
  std::array<float, 58> data{};

  bool operator==(const DebugFloatArray&) const = default;
};

// A CAN frame forwarded over MAVLink (up to 8 data bytes; the rig's convention, as SocketCAN's:
// bit 31 of id marks a 29-bit id).
struct CanFrame {
  static constexpr std::uint32_t kId = 386;
  static constexpr std::string_view kName = "CAN_FRAME";
  static constexpr std::uint8_t kCrcExtra = 132;
  static constexpr std::size_t kBasePayloadBytes = 16;
  static constexpr std::size_t kFullPayloadBytes = 16;

  std::uint32_t id = 0;
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint8_t bus = 0;
  std::uint8_t len = 0;  // data bytes used
  std::array<std::uint8_t, 8> data{};

  bool operator==(const CanFrame&) const = default;
};

using AnyMessage =
    std::variant<Heartbeat, SystemTime, CommandLong, CommandAck, SetPositionTargetLocalNed,
                 HilActuatorControls, VisionPositionEstimate, HilSensor, Timesync, HilGps, Odometry,
                 DebugFloatArray, CanFrame>;

template <typename M, typename Variant>
struct IsAlternativeOf;
template <typename M, typename... Ts>
struct IsAlternativeOf<M, std::variant<Ts...>>
    : std::bool_constant<(std::is_same_v<M, Ts> || ...)> {};

// One of the message structs above.
template <typename M>
concept KnownMessage = IsAlternativeOf<M, AnyMessage>::value;

// Writes `message` in wire layout, extensions included, into its full-length payload. Cannot
// fail; O(payload); does not allocate.
template <KnownMessage M>
void Pack(const M& message, std::span<std::uint8_t, M::kFullPayloadBytes> payload);

// Reads a message from its payload; bytes past the end of `full_payload` read as zero (the v2
// zero-extension rule) and bytes past the message's full length are ignored. Cannot fail;
// O(payload); does not allocate.
template <KnownMessage M>
M Unpack(std::span<const std::uint8_t> full_payload);

// One wire field, as the message definition names it.
struct FieldInfo {
  std::string_view type_name;     // "uint8_t", "float", ...; an array's element type
  std::string_view name;          // the definition's field name
  std::uint8_t array_length = 0;  // 0 for a scalar
  std::uint8_t element_bytes = 0;
  std::uint8_t offset = 0;  // in the payload
  bool extension = false;
};

struct MessageInfo {
  std::uint32_t id = 0;
  std::string_view name;
  std::uint8_t crc_extra = 0;  // the published value
  std::uint8_t base_payload_bytes = 0;
  std::uint8_t full_payload_bytes = 0;
  std::span<const FieldInfo> fields;  // wire order
};

// MAVLink's CRC_EXTRA rule: CRC of "NAME " then, for each base (non-extension) field in wire
// order, "type " and "name " and, for an array, its length as one byte; folded to 8 bits. Cannot
// fail; O(fields); does not allocate.
constexpr std::uint8_t CrcExtraFromFields(std::string_view message_name,
                                          std::span<const FieldInfo> fields) {
  std::uint16_t crc = CrcAccumulate(message_name, kCrcInit);
  crc = CrcAccumulate(std::uint8_t{' '}, crc);
  for (const FieldInfo& field : fields) {
    if (field.extension) continue;
    crc = CrcAccumulate(field.type_name, crc);
    crc = CrcAccumulate(std::uint8_t{' '}, crc);
    crc = CrcAccumulate(field.name, crc);
    crc = CrcAccumulate(std::uint8_t{' '}, crc);
    if (field.array_length != 0) crc = CrcAccumulate(field.array_length, crc);
  }
  return static_cast<std::uint8_t>((crc & 0xFF) ^ (crc >> 8));
}

// Every message above, in id order. Cannot fail; does not allocate.
std::span<const MessageInfo> AllMessages();

// The descriptor of message `id`, or null for an id not in the table. Cannot fail; O(number of
// messages); does not allocate.
const MessageInfo* FindMessage(std::uint32_t id);

// FindMessage reduced to what FrameParser needs; a WireInfoLookup. Cannot fail; O(number of
// messages); does not allocate.
std::optional<WireInfo> FindWireInfo(std::uint32_t id);

// The id of the message `message` holds. Cannot fail; does not allocate.
std::uint32_t MessageId(const AnyMessage& message);

// Packs `message` and frames it (unsigned, payload trimmed) into `out`; returns the frame's size,
// or 0 when `out` is too small (kMaxFrameBytes always suffices). O(payload); does not allocate.
std::size_t EncodeMessage(const AnyMessage& message, std::uint8_t sequence, std::uint8_t system_id,
                          std::uint8_t component_id, std::span<std::uint8_t> out);

// The typed message a parsed frame carries, its trimmed payload zero-extended; nullopt for an id
// not in the table or a payload longer than the message's full length. O(payload); does not
// allocate.
std::optional<AnyMessage> DecodeMessage(const Frame& frame);

}  // namespace hilrig::mavlink
