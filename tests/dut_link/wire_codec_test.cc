// dut_link/wire_codec.h against libprotobuf: what libprotobuf writes, the codec reads (unknown
// fields skipped), what the codec writes is byte for byte what libprotobuf writes and reads back,
// and broken input ends in a typed error, never a read past the end.
#include "dut_link/wire_codec.h"

#include <google/protobuf/unknown_field_set.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "proto/hil_link.pb.h"

namespace hilrig::dut_link::wire {
namespace {

std::vector<std::uint8_t> Bytes(const google::protobuf::MessageLite& message) {
  const std::string text = message.SerializeAsString();
  return {text.begin(), text.end()};
}

std::span<const std::uint8_t> View(const std::vector<std::uint8_t>& bytes) { return bytes; }

struct ImuRead {
  std::array<float, 6> gyro_accel{};
  std::size_t count = 0;
  std::int64_t time_offset_ns = 0;
};

ImuRead ReadImu(Reader reader, WireError* error = nullptr) {
  ImuRead out;
  while (const auto tag = reader.Next()) {
    if (tag->field == 1) reader.AppendFloats(out.gyro_accel, out.count);
    if (tag->field == 2) out.time_offset_ns = reader.SInt64();
  }
  if (error != nullptr) *error = reader.error();
  return out;
}

proto::SerialStep SampleStep() {
  proto::SerialStep step;
  step.set_tick(123456789012ULL);
  step.set_now_offset_ns(-37);
  proto::SerialImu* imu = step.add_inputs()->mutable_imu();
  for (const float value : {0.1f, -0.2f, 0.3f, 0.f, -9.81f, 1e-30f}) imu->add_gyro_accel(value);
  imu->set_time_offset_ns(-999'999);
  step.set_bridge_bytes(300);
  step.set_realtime(true);
  return step;
}

TEST(WireCodec, ReadsWhatLibprotobufWrites) {
  const std::vector<std::uint8_t> bytes = Bytes(SampleStep());
  Reader reader(View(bytes));
  std::uint64_t tick = 0;
  std::int64_t offset = 0;
  std::uint32_t bridge = 0;
  bool realtime = false;
  ImuRead imu;
  while (const auto tag = reader.Next()) {
    switch (tag->field) {
      case 1:
        tick = reader.Varint();
        break;
      case 2:
        offset = reader.SInt64();
        break;
      case 3: {
        Reader input = reader.Message();
        while (const auto inner = input.Next()) {
          if (inner->field == 1) imu = ReadImu(input.Message());
        }
        EXPECT_TRUE(input.ok());
        break;
      }
      case 4:
        bridge = reader.Uint32();
        break;
      case 5:
        realtime = reader.Bool();
        break;
      default:
        reader.Skip();
    }
  }
  ASSERT_EQ(reader.error(), WireError::kNone);
  EXPECT_EQ(tick, 123456789012ULL);
  EXPECT_EQ(offset, -37);
  EXPECT_EQ(bridge, 300u);
  EXPECT_TRUE(realtime);
  ASSERT_EQ(imu.count, 6u);
  EXPECT_EQ(imu.gyro_accel[4], -9.81f);
  EXPECT_EQ(imu.gyro_accel[5], 1e-30f);
  EXPECT_EQ(imu.time_offset_ns, -999'999);
}

TEST(WireCodec, ReadsDoublesAndPackedDoubles) {
  proto::Matrix3 matrix;
  for (int i = 0; i < 9; ++i) matrix.add_row_major(0.1 * i - 0.35);
  const std::vector<std::uint8_t> bytes = Bytes(matrix);
  Reader reader(View(bytes));
  std::array<double, 9> values{};
  std::size_t count = 0;
  while (const auto tag = reader.Next()) reader.AppendDoubles(values, count);
  ASSERT_TRUE(reader.ok());
  ASSERT_EQ(count, 9u);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(values[i], matrix.row_major(i));

  proto::Vector3 vector;
  vector.set_x(-1.0 / 3.0);
  vector.set_z(std::numeric_limits<double>::denorm_min());
  const std::vector<std::uint8_t> vbytes = Bytes(vector);
  Reader vreader(View(vbytes));
  std::array<double, 3> xyz{};
  while (const auto tag = vreader.Next()) xyz[tag->field - 1] = vreader.Double();
  EXPECT_TRUE(vreader.ok());
  EXPECT_EQ(xyz[0], -1.0 / 3.0);
  EXPECT_EQ(xyz[1], 0.0);
  EXPECT_EQ(xyz[2], std::numeric_limits<double>::denorm_min());
}

TEST(WireCodec, ZigZagMatchesLibprotobufAtTheExtremes) {
  for (const std::int64_t value :
       {std::numeric_limits<std::int64_t>::min(), std::int64_t(-1), std::int64_t(0),
        std::int64_t(1), std::numeric_limits<std::int64_t>::max()}) {
    proto::SerialImu imu;
    imu.set_time_offset_ns(value);
    const std::vector<std::uint8_t> bytes = Bytes(imu);
    EXPECT_EQ(ReadImu(Reader(View(bytes))).time_offset_ns, value);
    std::array<std::uint8_t, 16> out{};
    Writer writer(out);
    if (value != 0) writer.SInt64(2, value);
    EXPECT_EQ(std::vector<std::uint8_t>(writer.written().begin(), writer.written().end()), bytes);
  }
  for (const std::int32_t value : {std::numeric_limits<std::int32_t>::min(), -1, 0,
                                   std::numeric_limits<std::int32_t>::max()}) {
    std::array<std::uint8_t, 16> out{};
    Writer writer(out);
    writer.SInt64(1, value);
    Reader reader(writer.written());
    ASSERT_TRUE(reader.Next());
    EXPECT_EQ(reader.SInt32(), value);
  }
}

TEST(WireCodec, SkipsUnknownFieldsOfEveryWireType) {
  proto::SerialImu imu;
  imu.add_gyro_accel(1.5f);
  imu.set_time_offset_ns(-4);
  auto* unknown = imu.GetReflection()->MutableUnknownFields(&imu);
  unknown->AddVarint(40, 1ULL << 62);
  unknown->AddFixed32(41, 7);
  unknown->AddFixed64(42, 8);
  unknown->AddLengthDelimited(43, std::string(300, 'x'));
  const std::vector<std::uint8_t> bytes = Bytes(imu);
  WireError error = WireError::kNone;
  const ImuRead read = ReadImu(Reader(View(bytes)), &error);
  EXPECT_EQ(error, WireError::kNone);
  ASSERT_EQ(read.count, 1u);
  EXPECT_EQ(read.gyro_accel[0], 1.5f);
  EXPECT_EQ(read.time_offset_ns, -4);
}

// What a SerialCommand holds, written field by field as the DUT writes it.
std::vector<std::uint8_t> WriteCommand(std::span<std::uint8_t> out, WireError* error = nullptr) {
  Writer w(out);
  const auto message = w.BeginMessage(10);
  w.Varint(1, 70'000);
  const std::array<float, 4> thrust = {1.25f, 1.5f, -0.f, 3e38f};
  w.PackedFloats(2, thrust);
  w.Bool(3, true);
  w.Float(4, 0.75f);
  const std::array<float, 3> position = {0.5f, -0.25f, 1.f};
  w.PackedFloats(5, position);
  w.PackedFloats(8, position);
  std::array<float, 18> pads{};
  for (std::size_t i = 0; i < pads.size(); ++i) pads[i] = 0.01f * float(i + 1);
  w.PackedFloats(9, pads);
  const auto counters = w.BeginMessage(11);
  w.Varint(1, 70'001);
  w.Varint(9, 3);
  w.EndMessage(counters);
  w.EndMessage(message);
  if (error != nullptr) *error = w.error();
  return {w.written().begin(), w.written().end()};
}

// Packed doubles and varints as libprotobuf reads a repeated double and a repeated uint32.
TEST(WireCodec, WritesPackedDoublesAndVarintsLibprotobufReads) {
  std::array<std::uint8_t, 128> out{};
  Writer w(out);
  const std::array<double, 4> thrust = {1.25, -0.0, 1e300, 0.1};
  w.PackedDoubles(3, thrust);
  const std::array<std::uint16_t, 3> codes = {0, 300, 65535};
  w.PackedVarints<std::uint16_t>(2, codes);
  ASSERT_TRUE(w.ok());
  proto::ActuatorCommand command;
  const std::span<const std::uint8_t> thrust_bytes = w.written().first(2 + 32);
  ASSERT_TRUE(command.ParseFromArray(thrust_bytes.data(), static_cast<int>(thrust_bytes.size())));
  ASSERT_EQ(command.rotor_thrust_n_size(), 4);
  EXPECT_EQ(command.rotor_thrust_n(2), 1e300);
  EXPECT_TRUE(std::signbit(command.rotor_thrust_n(1)));
  // Key (field 2, length-delimited), length 6, then 0, 300 and 65535 as varints.
  const std::span<const std::uint8_t> code_bytes = w.written().subspan(2 + 32);
  EXPECT_EQ(std::vector<std::uint8_t>(code_bytes.begin(), code_bytes.end()),
            (std::vector<std::uint8_t>{0x12, 6, 0x00, 0xAC, 0x02, 0xFF, 0xFF, 0x03}));
}

TEST(WireCodec, WritesWhatLibprotobufWritesAndReads) {
  std::array<std::uint8_t, 512> out{};
  WireError error = WireError::kNone;
  const std::vector<std::uint8_t> written = WriteCommand(out, &error);
  ASSERT_EQ(error, WireError::kNone);
  ASSERT_GT(written.size(), 130u) << "the nested message must need a two-byte length";

  proto::LinkMessage expected;
  proto::SerialCommand* command = expected.mutable_serial_command();
  command->set_answers_tick(70'000);
  for (const float value : {1.25f, 1.5f, -0.f, 3e38f}) command->add_rotor_thrust_n(value);
  command->set_armed(true);
  command->set_servo_angle_rad(0.75f);
  for (const float value : {0.5f, -0.25f, 1.f}) {
    command->add_estimated_position_m(value);
    command->add_external_force_world_n(value);
  }
  for (int i = 0; i < 18; ++i) command->add_tactile_force_sensor_n(0.01f * float(i + 1));
  command->mutable_counters()->set_frames_received(70'001);
  command->mutable_counters()->set_bridge_bytes_missing(3);
  EXPECT_EQ(written, Bytes(expected));

  proto::LinkMessage parsed;
  ASSERT_TRUE(parsed.ParseFromArray(written.data(), int(written.size())));
  EXPECT_EQ(parsed.serial_command().tactile_force_sensor_n(17), 0.01f * float(18));
  EXPECT_EQ(parsed.serial_command().counters().bridge_bytes_missing(), 3u);
}

TEST(WireCodec, WriterReportsOverflowAndNeverWritesPastTheBuffer) {
  std::array<std::uint8_t, 512> full{};
  const std::size_t needed = WriteCommand(full).size();
  for (std::size_t size = 0; size < needed; ++size) {
    std::vector<std::uint8_t> out(size + 8, 0xEE);  // a guard past the writer's span
    WireError error = WireError::kNone;
    const auto written = WriteCommand(std::span(out.data(), size), &error);
    EXPECT_EQ(error, WireError::kOverflow) << "buffer of " << size;
    EXPECT_LE(written.size(), size);
    for (std::size_t i = size; i < out.size(); ++i) ASSERT_EQ(out[i], 0xEE) << "byte " << i;
  }
  std::vector<std::uint8_t> exact(needed);
  WireError error = WireError::kNone;
  EXPECT_EQ(WriteCommand(exact, &error).size(), needed);
  EXPECT_EQ(error, WireError::kNone);
}

// Reads every field of `bytes` as a SerialStep would be read, nested inputs included.
WireError ReadWholeStep(std::span<const std::uint8_t> bytes) {
  Reader reader(bytes);
  while (const auto tag = reader.Next()) {
    if (tag->field == 3) {
      Reader input = reader.Message();
      while (const auto inner = input.Next()) {
        WireError imu_error = WireError::kNone;
        ReadImu(input.Message(), &imu_error);
        if (imu_error != WireError::kNone) return imu_error;
      }
      if (!input.ok()) return input.error();
    } else {
      reader.Skip();
    }
  }
  return reader.error();
}

TEST(WireCodec, EveryTruncationIsTruncatedNeverAnOverrun) {
  const std::vector<std::uint8_t> bytes = Bytes(SampleStep());
  ASSERT_EQ(ReadWholeStep(bytes), WireError::kNone);
  int truncated = 0;
  for (std::size_t size = 0; size < bytes.size(); ++size) {
    // A copy of exactly `size` bytes, so a read past its end is a sanitizer error.
    const std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + std::ptrdiff_t(size));
    const WireError error = ReadWholeStep(cut);
    EXPECT_TRUE(error == WireError::kNone || error == WireError::kTruncated) << "size " << size;
    truncated += error == WireError::kTruncated;
  }
  // Cuts at a top-level field boundary parse (5 fields: 5 boundaries before the end, and 0).
  EXPECT_EQ(truncated, int(bytes.size()) - 5);
}

TEST(WireCodec, BadWireTypesAndOverlongVarintsAreTyped) {
  for (const std::uint8_t key : {0x0B, 0x0C, 0x0E, 0x0F}) {  // field 1, wire types 3, 4, 6, 7
    const std::vector<std::uint8_t> bytes = {key, 0x00};
    Reader reader(View(bytes));
    EXPECT_FALSE(reader.Next());
    EXPECT_EQ(reader.error(), WireError::kBadWireType) << int(key);
  }
  const std::vector<std::uint8_t> varint_field = {0x08, 0x05};  // field 1 varint
  Reader wrong(View(varint_field));
  ASSERT_TRUE(wrong.Next());
  EXPECT_EQ(wrong.Float(), 0.f);
  EXPECT_EQ(wrong.error(), WireError::kBadWireType);

  std::vector<std::uint8_t> eleven = {0x08};
  eleven.insert(eleven.end(), 10, 0x80);
  eleven.push_back(0x01);
  Reader overlong(View(eleven));
  ASSERT_TRUE(overlong.Next());
  EXPECT_EQ(overlong.Varint(), 0u);
  EXPECT_EQ(overlong.error(), WireError::kOverlongVarint);

  std::vector<std::uint8_t> beyond_64 = {0x08};
  beyond_64.insert(beyond_64.end(), 9, 0xFF);
  beyond_64.push_back(0x02);  // the tenth byte may carry one bit only
  Reader beyond(View(beyond_64));
  ASSERT_TRUE(beyond.Next());
  beyond.Varint();
  EXPECT_EQ(beyond.error(), WireError::kOverlongVarint);

  std::vector<std::uint8_t> max_64 = {0x08};
  max_64.insert(max_64.end(), 9, 0xFF);
  max_64.push_back(0x01);
  Reader max(View(max_64));
  ASSERT_TRUE(max.Next());
  EXPECT_EQ(max.Varint(), std::numeric_limits<std::uint64_t>::max());
  EXPECT_TRUE(max.ok());

  const std::vector<std::uint8_t> field_zero = {0x00, 0x01};
  Reader zero(View(field_zero));
  EXPECT_FALSE(zero.Next());
  EXPECT_EQ(zero.error(), WireError::kBadFieldNumber);
}

TEST(WireCodec, RepeatedFloatsPackedUnpackedAndBounded) {
  // Field 1 unpacked twice, then packed with two values: four values in all.
  const std::vector<std::uint8_t> mixed = {0x0D, 0x00, 0x00, 0x80, 0x3F,  // 1.0f
                                           0x0D, 0x00, 0x00, 0x00, 0x40,  // 2.0f
                                           0x0A, 0x08, 0x00, 0x00, 0x40,
                                           0x40, 0x00, 0x00, 0x80, 0x40};  // 3.0f, 4.0f
  std::array<float, 4> four{};
  std::size_t count = 0;
  Reader reader(View(mixed));
  while (reader.Next()) reader.AppendFloats(four, count);
  EXPECT_TRUE(reader.ok());
  EXPECT_EQ(count, 4u);
  EXPECT_EQ(four, (std::array<float, 4>{1.f, 2.f, 3.f, 4.f}));

  std::array<float, 3> three{};
  count = 0;
  Reader too_many(View(mixed));
  while (too_many.Next()) too_many.AppendFloats(three, count);
  EXPECT_EQ(too_many.error(), WireError::kTooManyValues);
  EXPECT_LE(count, 3u);

  const std::vector<std::uint8_t> ragged = {0x0A, 0x05, 0, 0, 0x80, 0x3F, 0};  // 5 bytes packed
  count = 0;
  Reader bad(View(ragged));
  while (bad.Next()) bad.AppendFloats(four, count);
  EXPECT_EQ(bad.error(), WireError::kTruncated);
}

}  // namespace
}  // namespace hilrig::dut_link::wire
