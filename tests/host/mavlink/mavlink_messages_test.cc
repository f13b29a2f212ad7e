// The typed messages: every descriptor against the published CRC_EXTRA, lengths and field offsets
// (the CRC_EXTRA recomputed from a field table only matches when the table's order, types and
// names are the definition's), round trips of every message through the framing in any chunking,
// the v2 trim and zero-extension rules, and known-good frames from another implementation.
#include "host/mavlink/mavlink_messages.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <random>
#include <string_view>
#include <vector>

namespace hilrig::mavlink {
namespace {

using Bytes = std::vector<std::uint8_t>;

struct Published {
  std::uint32_t id;
  std::string_view name;
  std::uint8_t crc_extra;
  std::uint8_t base_payload_bytes;  // without extensions
  std::uint8_t full_payload_bytes;  // with extensions
};

// As published for the common message set.
constexpr Published kPublished[] = {
    {0, "HEARTBEAT", 50, 9, 9},
    {2, "SYSTEM_TIME", 137, 12, 12},
    {76, "COMMAND_LONG", 152, 33, 33},
    {77, "COMMAND_ACK", 143, 3, 10},
    {84, "SET_POSITION_TARGET_LOCAL_NED", 143, 53, 53},
    {93, "HIL_ACTUATOR_CONTROLS", 47, 81, 81},
    {102, "VISION_POSITION_ESTIMATE", 158, 32, 117},
    {107, "HIL_SENSOR", 108, 64, 65},
    {111, "TIMESYNC", 34, 16, 18},
    {113, "HIL_GPS", 124, 36, 39},
    {331, "ODOMETRY", 91, 230, 233},
    {350, "DEBUG_FLOAT_ARRAY", 232, 20, 252},
    {386, "CAN_FRAME", 132, 16, 16},
};

// HEARTBEAT from system 1 component 1, seq 239, as another implementation's tests encode it.
const Bytes kKnownHeartbeat = {0xFD, 0x09, 0x00, 0x00, 0xEF, 0x01, 0x01, 0x00, 0x00, 0x00, 0x05,
                               0x00, 0x00, 0x00, 0x02, 0x03, 0x59, 0x03, 0x03, 0x10, 0xF0};
// COMMAND_LONG MAV_CMD_SET_MESSAGE_INTERVAL for message 115 every 5000 us, trimmed to 30 bytes.
const Bytes kKnownTrimmedCommandLong = {
    0xFD, 0x1E, 0x00, 0x00, 0x00, 0x00, 0x32, 0x4C, 0x00, 0x00, 0x00, 0x00, 0xE6, 0x42,
    0x00, 0x40, 0x9C, 0x45, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xFF, 0x01, 0xBC, 0xC3};

std::optional<std::uint8_t> OffsetOf(const MessageInfo& info, std::string_view field) {
  for (const FieldInfo& f : info.fields) {
    if (f.name == field) return f.offset;
  }
  return std::nullopt;
}

// Every field set, extensions included, none to a value whose bytes are all zero.
std::vector<AnyMessage> Samples() {
  Heartbeat heartbeat{.custom_mode = 0x01020304,
                      .type = 2,
                      .autopilot = 12,
                      .base_mode = 0x81,
                      .system_status = 4,
                      .mavlink_version = 3};
  SystemTime system_time{.time_unix_usec = 1'700'000'000'123'456ull, .time_boot_ms = 987'654};
  CommandLong command_long{.param1 = 1.5f,
                           .param2 = -2.25f,
                           .param3 = 3e6f,
                           .param4 = -4e-6f,
                           .param5 = 47.3977f,
                           .param6 = 8.5456f,
                           .param7 = 488.0f,
                           .command = 400,
                           .target_system = 1,
                           .target_component = 1,
                           .confirmation = 2};
  CommandAck command_ack{.command = 511,
                         .result = 5,
                         .progress = 42,
                         .result_param2 = -123456,
                         .target_system = 255,
                         .target_component = 190};
  SetPositionTargetLocalNed setpoint{.time_boot_ms = 12345,
                                     .x_m = 1.0f,
                                     .y_m = -2.0f,
                                     .z_m = -10.5f,
                                     .vx_m_s = 0.5f,
                                     .vy_m_s = -0.25f,
                                     .vz_m_s = 0.125f,
                                     .afx_m_s2 = 0.1f,
                                     .afy_m_s2 = 0.2f,
                                     .afz_m_s2 = -9.81f,
                                     .yaw_rad = 1.57f,
                                     .yaw_rate_rad_s = -0.3f,
                                     .type_mask = 0x0DF8,
                                     .target_system = 1,
                                     .target_component = 1,
                                     .coordinate_frame = 1};
  HilActuatorControls actuators{.time_usec = 42'000'000, .flags = 1, .controls = {}, .mode = 0x81};
  for (std::size_t i = 0; i < actuators.controls.size(); ++i) {
    actuators.controls[i] = -1.0f + 0.125f * static_cast<float>(i);
  }
  actuators.controls[8] = 0.0625f;  // -1 + 8 * 0.125 would be 0
  VisionPositionEstimate vision{.usec = 123'456'789,
                                .x_m = 0.1f,
                                .y_m = 0.2f,
                                .z_m = -0.3f,
                                .roll_rad = 0.01f,
                                .pitch_rad = -0.02f,
                                .yaw_rad = 3.1f,
                                .covariance = {},
                                .reset_counter = 7};
  for (std::size_t i = 0; i < vision.covariance.size(); ++i) {
    vision.covariance[i] = 0.001f * static_cast<float>(i + 1);
  }
  HilSensor sensor{.time_usec = 1'000'000,
                   .xacc_m_s2 = 0.12f,
                   .yacc_m_s2 = -0.34f,
                   .zacc_m_s2 = -9.80665f,
                   .xgyro_rad_s = 0.01f,
                   .ygyro_rad_s = -0.02f,
                   .zgyro_rad_s = 0.03f,
                   .xmag_gauss = 0.21f,
                   .ymag_gauss = 0.01f,
                   .zmag_gauss = 0.42f,
                   .abs_pressure_hpa = 1013.25f,
                   .diff_pressure_hpa = 0.5f,
                   .pressure_alt = 488.0f,
                   .temperature_degc = 21.5f,
                   .fields_updated = 0x1FFF,
                   .id = 1};
  Timesync timesync{
      .tc1_ns = -5, .ts1_ns = 1'234'567'890'123, .target_system = 1, .target_component = 240};
  HilGps gps{.time_usec = 2'000'000,
             .lat_deg_e7 = 473977418,
             .lon_deg_e7 = -85455939,
             .alt_mm = 488'000,
             .eph = 80,
             .epv = 120,
             .vel_cm_s = 1234,
             .vn_cm_s = -1000,
             .ve_cm_s = 700,
             .vd_cm_s = -15,
             .cog_cdeg = 35999,
             .fix_type = 3,
             .satellites_visible = 12,
             .id = 1,
             .yaw_cdeg = 36000};
  Odometry odometry{.time_usec = 3'000'000,
                    .x_m = 1.0f,
                    .y_m = 2.0f,
                    .z_m = -3.0f,
                    .q = {0.7071f, 0.0f, 0.0f, 0.7071f},
                    .vx_m_s = 0.1f,
                    .vy_m_s = 0.2f,
                    .vz_m_s = 0.3f,
                    .rollspeed_rad_s = 0.01f,
                    .pitchspeed_rad_s = 0.02f,
                    .yawspeed_rad_s = 0.03f,
                    .pose_covariance = {},
                    .velocity_covariance = {},
                    .frame_id = 1,
                    .child_frame_id = 12,
                    .reset_counter = 2,
                    .estimator_type = 6,
                    .quality_percent = -1};
  for (std::size_t i = 0; i < 21; ++i) {
    odometry.pose_covariance[i] = 0.01f * static_cast<float>(i + 1);
    odometry.velocity_covariance[i] = -0.5f * static_cast<float>(i + 1);
  }
  DebugFloatArray debug{
      .time_usec = 4'000'000, .array_id = 1, .name = {'h', 'i', 'l', 'r', 'i', 'g'}};
  for (std::size_t i = 0; i < debug.data.size(); ++i) {
    debug.data[i] = 0.5f * static_cast<float>(i) - 7.0f;
  }
  CanFrame can{.id = 0x123,
               .target_system = 1,
               .target_component = 1,
               .bus = 0,
               .len = 8,
               .data = {1, 2, 3, 4, 5, 6, 7, 0xFF}};
  return {heartbeat, system_time, command_long, command_ack, setpoint, actuators, vision,
          sensor,    timesync,    gps,          odometry,    debug,    can};
}

Bytes EncodeToBytes(const AnyMessage& message, std::uint8_t sequence = 17) {
  Bytes out(kMaxFrameBytes);
  out.resize(EncodeMessage(message, sequence, 42, 200, out));
  return out;
}

std::vector<Frame> ParseInChunks(const Bytes& bytes, std::size_t chunk) {
  FrameParser parser(&FindWireInfo);
  std::vector<Frame> frames;
  for (std::size_t at = 0; at < bytes.size(); at += chunk) {
    parser.Feed(
        std::span<const std::uint8_t>(bytes).subspan(at, std::min(chunk, bytes.size() - at)),
        [&](const Frame& frame) { frames.push_back(frame); });
  }
  EXPECT_EQ(parser.counters(), (ParserCounters{.frames_ok = frames.size()}));
  return frames;
}

TEST(MavlinkMessagesTest, DescriptorsMatchThePublishedDefinitions) {
  ASSERT_EQ(AllMessages().size(), std::size(kPublished));
  for (const Published& published : kPublished) {
    SCOPED_TRACE(published.name);
    const MessageInfo* info = FindMessage(published.id);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(info->name, published.name);
    EXPECT_EQ(info->crc_extra, published.crc_extra);
    EXPECT_EQ(info->base_payload_bytes, published.base_payload_bytes);
    EXPECT_EQ(info->full_payload_bytes, published.full_payload_bytes);
  }
}

TEST(MavlinkMessagesTest, CrcExtraRecomputedFromEachFieldTableIsThePublishedOne) {
  for (const Published& published : kPublished) {
    SCOPED_TRACE(published.name);
    const MessageInfo* info = FindMessage(published.id);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(CrcExtraFromFields(info->name, info->fields), published.crc_extra);
  }
}

TEST(MavlinkMessagesTest, FieldTablesAreInWireOrderWithContiguousOffsets) {
  for (const MessageInfo& info : AllMessages()) {
    SCOPED_TRACE(info.name);
    std::size_t offset = 0;
    std::size_t base_bytes = 0;
    bool extensions = false;
    std::uint8_t previous_base_size = 8;
    for (const FieldInfo& field : info.fields) {
      SCOPED_TRACE(field.name);
      EXPECT_EQ(field.offset, offset);
      if (field.extension) {
        extensions = true;
      } else {
        EXPECT_FALSE(extensions) << "a base field after an extension";
        EXPECT_LE(field.element_bytes, previous_base_size) << "base fields sort by size";
        previous_base_size = field.element_bytes;
      }
      offset += field.element_bytes * std::max<std::size_t>(field.array_length, 1);
      if (!field.extension) base_bytes = offset;
    }
    EXPECT_EQ(base_bytes, info.base_payload_bytes);
    EXPECT_EQ(offset, info.full_payload_bytes);
  }
}

TEST(MavlinkMessagesTest, FieldOffsetsMatchThePublishedLayouts) {
  struct Expected {
    std::uint32_t id;
    std::string_view field;
    std::uint8_t offset;
  };
  const Expected expected[] = {
      {0, "custom_mode", 0},
      {0, "type", 4},
      {0, "mavlink_version", 8},
      {2, "time_boot_ms", 8},
      {76, "command", 28},
      {76, "confirmation", 32},
      {77, "result", 2},
      {77, "progress", 3},
      {77, "result_param2", 4},
      {77, "target_component", 9},
      {84, "yaw_rate", 44},
      {84, "type_mask", 48},
      {84, "coordinate_frame", 52},
      {93, "flags", 8},
      {93, "controls", 16},
      {93, "mode", 80},
      {102, "covariance", 32},
      {102, "reset_counter", 116},
      {107, "temperature", 56},
      {107, "fields_updated", 60},
      {107, "id", 64},
      {111, "ts1", 8},
      {111, "target_system", 16},
      {111, "target_component", 17},
      {113, "lat", 8},
      {113, "cog", 32},
      {113, "fix_type", 34},
      {113, "satellites_visible", 35},
      {113, "id", 36},
      {113, "yaw", 37},
      {331, "q", 20},
      {331, "pose_covariance", 60},
      {331, "velocity_covariance", 144},
      {331, "frame_id", 228},
      {331, "child_frame_id", 229},
      {331, "reset_counter", 230},
      {331, "estimator_type", 231},
      {331, "quality", 232},
      {350, "array_id", 8},
      {350, "name", 10},
      {350, "data", 20},
      {386, "target_system", 4},
      {386, "len", 7},
      {386, "data", 8},
  };
  for (const Expected& e : expected) {
    const MessageInfo* info = FindMessage(e.id);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(OffsetOf(*info, e.field), e.offset) << info->name << "." << e.field;
  }
}

TEST(MavlinkMessagesTest, PacksLittleEndianAtTheTableOffsets) {
  HilGps gps;
  gps.lat_deg_e7 = 0x01020304;
  gps.yaw_cdeg = 0xA1B2;
  std::array<std::uint8_t, HilGps::kFullPayloadBytes> payload{};
  Pack(gps, std::span(payload));
  EXPECT_EQ(payload[8], 0x04);
  EXPECT_EQ(payload[11], 0x01);
  EXPECT_EQ(payload[37], 0xB2);  // an extension field straddling an odd offset
  EXPECT_EQ(payload[38], 0xA1);

  HilSensor sensor;
  sensor.xacc_m_s2 = 1.0f;  // 0x3F800000
  sensor.id = 9;
  std::array<std::uint8_t, HilSensor::kFullPayloadBytes> sensor_payload{};
  Pack(sensor, std::span(sensor_payload));
  EXPECT_EQ(sensor_payload[8], 0x00);
  EXPECT_EQ(sensor_payload[10], 0x80);
  EXPECT_EQ(sensor_payload[11], 0x3F);
  EXPECT_EQ(sensor_payload[64], 9);
}

TEST(MavlinkMessagesTest, EveryMessageRoundTripsThroughAFrameInAnyChunking) {
  for (const AnyMessage& sample : Samples()) {
    SCOPED_TRACE(FindMessage(MessageId(sample))->name);
    const Bytes wire = EncodeToBytes(sample);
    ASSERT_FALSE(wire.empty());
    for (const std::size_t chunk : {std::size_t{1}, std::size_t{2}, std::size_t{3}, std::size_t{7},
                                    std::size_t{64}, wire.size()}) {
      const std::vector<Frame> frames = ParseInChunks(wire, chunk);
      ASSERT_EQ(frames.size(), 1u);
      EXPECT_EQ(frames[0].sequence, 17);
      EXPECT_EQ(frames[0].system_id, 42);
      EXPECT_EQ(frames[0].component_id, 200);
      EXPECT_EQ(frames[0].message_id, MessageId(sample));
      const std::optional<AnyMessage> decoded = DecodeMessage(frames[0]);
      ASSERT_TRUE(decoded.has_value());
      EXPECT_EQ(*decoded, sample);
    }
  }
}

TEST(MavlinkMessagesTest, AllMessagesBackToBackByteAtATime) {
  Bytes stream;
  const std::vector<AnyMessage> samples = Samples();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Bytes wire = EncodeToBytes(samples[i], static_cast<std::uint8_t>(i));
    stream.insert(stream.end(), wire.begin(), wire.end());
  }
  const std::vector<Frame> frames = ParseInChunks(stream, 1);
  ASSERT_EQ(frames.size(), samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(frames[i].sequence, i);
    EXPECT_EQ(DecodeMessage(frames[i]), samples[i]);
  }
}

TEST(MavlinkMessagesTest, ZeroValuedMessagesTravelAsOneByte) {
  for (const AnyMessage& zero :
       {AnyMessage(SystemTime{}), AnyMessage(Odometry{}), AnyMessage(HilActuatorControls{})}) {
    const Bytes wire = EncodeToBytes(zero);
    ASSERT_EQ(wire.size(), kHeaderBytes + 1 + kChecksumBytes);
    const std::vector<Frame> frames = ParseInChunks(wire, wire.size());
    ASSERT_EQ(frames.size(), 1u);
    EXPECT_EQ(DecodeMessage(frames[0]), zero);
  }
}

TEST(MavlinkMessagesTest, UnsetExtensionsAreTrimmedAndDecodeAsZero) {
  HilSensor sensor = std::get<HilSensor>(Samples()[7]);
  sensor.id = 0;
  sensor.fields_updated = 0x80000001;  // a non-zero last base byte
  Bytes wire = EncodeToBytes(sensor);
  EXPECT_EQ(wire[1], HilSensor::kBasePayloadBytes);
  EXPECT_EQ(DecodeMessage(ParseInChunks(wire, 5).at(0)), AnyMessage(sensor));

  CommandAck ack{.command = 400, .result = 0};
  wire = EncodeToBytes(ack);
  EXPECT_EQ(wire[1], 2);  // result 0 is trimmed as well
  EXPECT_EQ(DecodeMessage(ParseInChunks(wire, 1).at(0)), AnyMessage(ack));

  Odometry odometry = std::get<Odometry>(Samples()[10]);
  odometry.reset_counter = 0;
  odometry.estimator_type = 0;
  odometry.quality_percent = 0;
  wire = EncodeToBytes(odometry);
  EXPECT_EQ(wire[1], Odometry::kBasePayloadBytes);
  EXPECT_EQ(DecodeMessage(ParseInChunks(wire, 3).at(0)), AnyMessage(odometry));
}

TEST(MavlinkMessagesTest, UnpackZeroExtendsAShortPayload) {
  const HilGps gps = std::get<HilGps>(Samples()[9]);
  std::array<std::uint8_t, HilGps::kFullPayloadBytes> payload{};
  Pack(gps, std::span(payload));
  HilGps expected = gps;
  expected.id = 0;
  expected.yaw_cdeg = 0;
  EXPECT_EQ(Unpack<HilGps>(std::span<const std::uint8_t>(payload).first(HilGps::kBasePayloadBytes)),
            expected);
  EXPECT_EQ(Unpack<HilGps>({}), HilGps{});
}

TEST(MavlinkMessagesTest, PackOfUnpackIsBitExactForAnyPayload) {
  // NaNs included: every float is carried by its bits.
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    std::array<std::uint8_t, 255> bytes{};
    for (std::uint8_t& b : bytes) b = static_cast<std::uint8_t>(rng());
    Frame frame;
    for (const MessageInfo& info : AllMessages()) {
      frame.message_id = info.id;
      frame.payload_length = info.full_payload_bytes;
      std::copy_n(bytes.begin(), info.full_payload_bytes, frame.payload.begin());
      const std::optional<AnyMessage> message = DecodeMessage(frame);
      ASSERT_TRUE(message.has_value());
      std::visit(
          [&](const auto& m) {
            using M = std::remove_cvref_t<decltype(m)>;
            std::array<std::uint8_t, M::kFullPayloadBytes> again{};
            Pack(m, std::span(again));
            EXPECT_TRUE(std::equal(again.begin(), again.end(), bytes.begin())) << info.name;
          },
          *message);
    }
  }
}

TEST(MavlinkMessagesTest, DecodesAndReencodesAKnownHeartbeat) {
  const std::vector<Frame> frames = ParseInChunks(kKnownHeartbeat, 1);
  ASSERT_EQ(frames.size(), 1u);
  const Heartbeat expected{.custom_mode = 5,
                           .type = 2,
                           .autopilot = 3,
                           .base_mode = 0x59,
                           .system_status = 3,
                           .mavlink_version = 3};
  EXPECT_EQ(DecodeMessage(frames[0]), AnyMessage(expected));
  Bytes out(kMaxFrameBytes);
  out.resize(EncodeMessage(expected, 0xEF, 1, 1, out));
  EXPECT_EQ(out, kKnownHeartbeat);
}

TEST(MavlinkMessagesTest, DecodesAndReencodesAKnownTrimmedCommandLong) {
  const std::vector<Frame> frames = ParseInChunks(kKnownTrimmedCommandLong, 4);
  ASSERT_EQ(frames.size(), 1u);
  const CommandLong expected{.param1 = 115.0f, .param2 = 5000.0f, .command = 511};
  EXPECT_EQ(DecodeMessage(frames[0]), AnyMessage(expected));
  Bytes out(kMaxFrameBytes);
  out.resize(EncodeMessage(expected, 0, 0, 50, out));
  EXPECT_EQ(out, kKnownTrimmedCommandLong);
}

TEST(MavlinkMessagesTest, DecodeRefusesUnknownIdsAndOverlongPayloads) {
  Frame frame;
  frame.message_id = 22;  // PARAM_VALUE: not in the table
  frame.payload_length = 25;
  EXPECT_FALSE(DecodeMessage(frame).has_value());
  frame.message_id = Heartbeat::kId;
  frame.payload_length = Heartbeat::kFullPayloadBytes + 1;
  EXPECT_FALSE(DecodeMessage(frame).has_value());
  frame.payload_length = Heartbeat::kFullPayloadBytes;
  EXPECT_TRUE(DecodeMessage(frame).has_value());
}

TEST(MavlinkMessagesTest, LooksUpWireInfo) {
  EXPECT_EQ(FindMessage(1), nullptr);
  EXPECT_FALSE(FindWireInfo(1).has_value());
  const std::optional<WireInfo> odometry = FindWireInfo(Odometry::kId);
  ASSERT_TRUE(odometry.has_value());
  EXPECT_EQ(odometry->crc_extra, 91);
  EXPECT_EQ(odometry->full_payload_bytes, 233);
  EXPECT_EQ(MessageId(AnyMessage(Timesync{})), 111u);
}

TEST(MavlinkMessagesTest, EncodeFailsIntoASmallBuffer) {
  Bytes out(kHeaderBytes);
  EXPECT_EQ(EncodeMessage(Samples()[0], 0, 1, 1, out), 0u);
}

}  // namespace
}  // namespace hilrig::mavlink
