// The telemetry log format: big-endian microsecond timestamps before whole frames, written to a
// stream and split back into records, including logs with damaged records, v1 frames and a
// cut-off tail.
#include "host/mavlink/tlog.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace hilrig::mavlink {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes EncodeToBytes(const AnyMessage& message, std::uint8_t sequence) {
  Bytes out(kMaxFrameBytes);
  out.resize(EncodeMessage(message, sequence, 1, 1, out));
  return out;
}

Frame ParseOne(const Bytes& wire) {
  FrameParser parser(&FindWireInfo);
  parser.Push(wire);
  return parser.Next().value();
}

Bytes ToBytes(const std::string& text) { return Bytes(text.begin(), text.end()); }

struct Log {
  Bytes bytes;
  std::vector<TlogRecord> records;
  std::vector<std::size_t> record_starts;  // byte offsets in `bytes`
};

Log WriteLog() {
  std::ostringstream out;
  TlogWriter writer(out);
  Log log;
  const std::vector<AnyMessage> messages = {
      Heartbeat{.custom_mode = 4, .type = 2, .autopilot = 12, .base_mode = 0x81},
      HilSensor{.time_usec = 1000, .zacc_m_s2 = -9.81f, .abs_pressure_hpa = 1013.25f, .id = 1},
      HilGps{.time_usec = 2000, .lat_deg_e7 = 473977418, .lon_deg_e7 = 85455939, .fix_type = 3},
      HilActuatorControls{.time_usec = 3000, .flags = 1, .controls = {0.5f, -0.5f}, .mode = 0x80},
  };
  std::uint64_t time_us = 1'700'000'000'000'000ull;
  std::uint8_t sequence = 0;
  for (const AnyMessage& message : messages) {
    const Bytes wire = EncodeToBytes(message, sequence++);
    log.record_starts.push_back(out.str().size());
    EXPECT_TRUE(writer.Write(time_us, wire));
    log.records.push_back({time_us, ParseOne(wire)});
    time_us += 4000;
  }
  log.bytes = ToBytes(out.str());
  return log;
}

TEST(TlogTest, WritesABigEndianTimestampThenTheFrame) {
  std::ostringstream out;
  TlogWriter writer(out);
  const Bytes frame = EncodeToBytes(Heartbeat{}, 5);
  ASSERT_TRUE(writer.Write(0x0102030405060708ull, frame));
  const Bytes written = ToBytes(out.str());
  ASSERT_EQ(written.size(), kTlogTimestampBytes + frame.size());
  const Bytes stamp(written.begin(), written.begin() + kTlogTimestampBytes);
  EXPECT_EQ(stamp, (Bytes{0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08}));
  EXPECT_EQ(Bytes(written.begin() + kTlogTimestampBytes, written.end()), frame);
}

TEST(TlogTest, RefusesEmptyAndOversizedFrames) {
  std::ostringstream out;
  TlogWriter writer(out);
  EXPECT_FALSE(writer.Write(1, {}));
  const Bytes oversized(kMaxSignedFrameBytes + 1, 0xFD);
  EXPECT_FALSE(writer.Write(1, oversized));
  EXPECT_TRUE(out.str().empty());
}

TEST(TlogTest, ReportsAFailedStream) {
  std::ostringstream out;
  out.setstate(std::ios::badbit);
  TlogWriter writer(out);
  EXPECT_FALSE(writer.Write(1, EncodeToBytes(Heartbeat{}, 0)));
}

TEST(TlogTest, ReadsBackWhatItWrote) {
  const Log log = WriteLog();
  const TlogContents contents = ReadTlog(log.bytes);
  EXPECT_EQ(contents.records, log.records);
  EXPECT_EQ(contents.v1_records_skipped, 0u);
  EXPECT_EQ(contents.bytes_skipped, 0u);
  ASSERT_EQ(contents.records.size(), 4u);
  EXPECT_EQ(
      DecodeMessage(contents.records[2].frame),
      AnyMessage(HilGps{
          .time_usec = 2000, .lat_deg_e7 = 473977418, .lon_deg_e7 = 85455939, .fix_type = 3}));
}

TEST(TlogTest, ReadsAnEmptyLog) {
  const TlogContents contents = ReadTlog({});
  EXPECT_TRUE(contents.records.empty());
  EXPECT_EQ(contents.bytes_skipped, 0u);
}

TEST(TlogTest, SkipsADamagedRecordAndKeepsTheRest) {
  Log log = WriteLog();
  const std::size_t second_record_size = log.record_starts[2] - log.record_starts[1];
  log.bytes[log.record_starts[2] - 1] ^= 0x01;  // the second frame's checksum
  const TlogContents contents = ReadTlog(log.bytes);
  ASSERT_EQ(contents.records.size(), 3u);
  EXPECT_EQ(contents.records[0], log.records[0]);
  EXPECT_EQ(contents.records[1], log.records[2]);
  EXPECT_EQ(contents.records[2], log.records[3]);
  EXPECT_EQ(contents.bytes_skipped, second_record_size);
}

TEST(TlogTest, CountsACutOffTail) {
  Log log = WriteLog();
  log.bytes.resize(log.bytes.size() - 5);
  const TlogContents contents = ReadTlog(log.bytes);
  ASSERT_EQ(contents.records.size(), 3u);
  EXPECT_EQ(contents.records[2], log.records[2]);
  const std::size_t last_record_size = log.bytes.size() + 5 - log.record_starts[3];
  EXPECT_EQ(contents.bytes_skipped, last_record_size - 5);
}

TEST(TlogTest, SkipsV1RecordsWhole) {
  const Bytes v1_heartbeat = {0xFE, 0x09, 0xEF, 0x01, 0x02, 0x00, 0x05, 0x00, 0x00,
                              0x00, 0x02, 0x03, 0x59, 0x03, 0x03, 0x1F, 0x50};
  std::ostringstream out;
  TlogWriter writer(out);
  const Bytes v2 = EncodeToBytes(Timesync{.tc1_ns = 0, .ts1_ns = 77}, 1);
  ASSERT_TRUE(writer.Write(10, v1_heartbeat));
  ASSERT_TRUE(writer.Write(20, v2));
  const TlogContents contents = ReadTlog(ToBytes(out.str()));
  ASSERT_EQ(contents.records.size(), 1u);
  EXPECT_EQ(contents.records[0].time_us, 20u);
  EXPECT_EQ(contents.records[0].frame, ParseOne(v2));
  EXPECT_EQ(contents.v1_records_skipped, 1u);
  EXPECT_EQ(contents.bytes_skipped, 0u);
}

TEST(TlogTest, KeepsSignedFrames) {
  const Bytes signed_heartbeat = {0xFD, 0x09, 0x01, 0x00, 0xEF, 0x01, 0x02, 0x00, 0x00,
                                  0x00, 0x05, 0x00, 0x00, 0x00, 0x02, 0x03, 0x59, 0x03,
                                  0x03, 0xC9, 0x8B, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
                                  0xFF, 0x27, 0x18, 0xB1, 0x68, 0xCC, 0xF5};
  std::ostringstream out;
  TlogWriter writer(out);
  ASSERT_TRUE(writer.Write(99, signed_heartbeat));
  ASSERT_TRUE(writer.Write(100, EncodeToBytes(Heartbeat{}, 1)));
  const TlogContents contents = ReadTlog(ToBytes(out.str()));
  ASSERT_EQ(contents.records.size(), 2u);
  EXPECT_EQ(contents.records[0].frame.incompat_flags, kIncompatSigned);
  EXPECT_EQ(contents.records[1].time_us, 100u);
}

}  // namespace
}  // namespace hilrig::mavlink
