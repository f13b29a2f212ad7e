// MAVLink v2 framing: the checksum, the encoder's zero-trim rule, and the stream parser's
// resynchronisation and counters. Known-good byte sequences are real frames as other MAVLink
// implementations produce them; the rest are built with the encoder and then damaged. Messages
// are described by a small table here, so these tests do not depend on the message layouts.
#include "host/mavlink/mavlink_frame.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

namespace hilrig::mavlink {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::uint32_t kHeartbeatId = 0;
constexpr std::uint32_t kCommandLongId = 76;
constexpr std::uint32_t kHilSensorId = 107;
constexpr std::uint32_t kWideId = 0x123456;  // needs all three message id bytes

std::optional<WireInfo> TestLookup(std::uint32_t id) {
  switch (id) {
    case kHeartbeatId:
      return WireInfo{50, 9};
    case kCommandLongId:
      return WireInfo{152, 33};
    case kHilSensorId:
      return WireInfo{108, 65};
    case kWideId:
      return WireInfo{0x5A, 40};
    default:
      return std::nullopt;
  }
}

// Knows no message, so every v1 frame is trusted and every v2 frame is unknown.
std::optional<WireInfo> EmptyLookup(std::uint32_t) { return std::nullopt; }

// A HEARTBEAT (custom_mode 5, quadrotor, ArduPilot, mode flags 0x59, standby, version 3), seq 239,
// from system 1 component 1, as another implementation's tests encode it.
const Bytes kKnownHeartbeat = {0xFD, 0x09, 0x00, 0x00, 0xEF, 0x01, 0x01, 0x00, 0x00, 0x00, 0x05,
                               0x00, 0x00, 0x00, 0x02, 0x03, 0x59, 0x03, 0x03, 0x10, 0xF0};
// The same message from component 2.
const Bytes kKnownHeartbeatComponent2 = {0xFD, 0x09, 0x00, 0x00, 0xEF, 0x01, 0x02,
                                         0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00,
                                         0x02, 0x03, 0x59, 0x03, 0x03, 0x2E, 0x73};
// The same message from component 2, signed: link id 0, timestamp 0xFFFFFFFFFFFF, signature.
const Bytes kKnownSignedHeartbeat = {0xFD, 0x09, 0x01, 0x00, 0xEF, 0x01, 0x02, 0x00, 0x00,
                                     0x00, 0x05, 0x00, 0x00, 0x00, 0x02, 0x03, 0x59, 0x03,
                                     0x03, 0xC9, 0x8B, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
                                     0xFF, 0x27, 0x18, 0xB1, 0x68, 0xCC, 0xF5};
// The same message as a MAVLink v1 frame.
const Bytes kKnownV1Heartbeat = {0xFE, 0x09, 0xEF, 0x01, 0x02, 0x00, 0x05, 0x00, 0x00,
                                 0x00, 0x02, 0x03, 0x59, 0x03, 0x03, 0x1F, 0x50};
// COMMAND_LONG MAV_CMD_SET_MESSAGE_INTERVAL (511), param1 115 (message id), param2 5000 (us), from
// system 0 component 50, seq 0: the three zero target/confirmation bytes are trimmed (30 of 33).
const Bytes kKnownTrimmedCommandLong = {
    0xFD, 0x1E, 0x00, 0x00, 0x00, 0x00, 0x32, 0x4C, 0x00, 0x00, 0x00, 0x00, 0xE6, 0x42,
    0x00, 0x40, 0x9C, 0x45, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xFF, 0x01, 0xBC, 0xC3};

Bytes Concat(std::initializer_list<Bytes> parts) {
  Bytes all;
  for (const Bytes& part : parts) all.insert(all.end(), part.begin(), part.end());
  return all;
}

Bytes Encode(const Frame& frame) {
  Bytes out(kMaxFrameBytes);
  const std::size_t size =
      EncodeFrame(frame, TestLookup(frame.message_id).value_or(WireInfo{}).crc_extra, out);
  out.resize(size);
  return out;
}

Frame HeartbeatFrame(std::uint8_t sequence) {
  Frame frame;
  frame.sequence = sequence;
  frame.system_id = 1;
  frame.component_id = 1;
  frame.message_id = kHeartbeatId;
  frame.payload_length = 9;
  const Bytes payload = {0x05, 0x00, 0x00, 0x00, 0x02, 0x03, 0x59, 0x03, 0x03};
  std::copy(payload.begin(), payload.end(), frame.payload.begin());
  return frame;
}

// A HIL_SENSOR-sized frame whose bytes are 1..65: no start byte in the payload.
Frame CountingSensorFrame(std::uint8_t sequence) {
  Frame frame;
  frame.sequence = sequence;
  frame.system_id = 1;
  frame.component_id = 1;
  frame.message_id = kHilSensorId;
  frame.payload_length = 65;
  for (std::size_t i = 0; i < 65; ++i) frame.payload[i] = static_cast<std::uint8_t>(i + 1);
  return frame;
}

bool HasStartByteAfterFirst(const Bytes& bytes) {
  return std::any_of(bytes.begin() + 1, bytes.end(),
                     [](std::uint8_t b) { return b == kStartV2 || b == kStartV1; });
}

struct Parsed {
  std::vector<Frame> frames;
  ParserCounters counters;
};

Parsed Parse(const Bytes& bytes, std::size_t chunk, bool finish = false,
             WireInfoLookup lookup = &TestLookup) {
  FrameParser parser(lookup);
  Parsed parsed;
  const auto keep = [&](const Frame& frame) { parsed.frames.push_back(frame); };
  for (std::size_t at = 0; at < bytes.size(); at += chunk) {
    const std::size_t n = std::min(chunk, bytes.size() - at);
    parser.Feed(std::span<const std::uint8_t>(bytes).subspan(at, n), keep);
  }
  if (finish) {
    parser.Finish();
    while (std::optional<Frame> frame = parser.Next()) keep(*frame);
  }
  parsed.counters = parser.counters();
  return parsed;
}

Parsed ParseWhole(const Bytes& bytes, bool finish = false) {
  return Parse(bytes, std::max<std::size_t>(bytes.size(), 1), finish);
}

// What a parsed frame holds when `sent` (full-length payload) went through the encoder.
Frame AsReceived(Frame sent) {
  sent.payload_length = static_cast<std::uint8_t>(TrimmedPayloadLength(
      std::span<const std::uint8_t>(sent.payload.data(), sent.payload_length)));
  std::fill(sent.payload.begin() + sent.payload_length, sent.payload.end(), 0);
  return sent;
}

TEST(MavlinkCrcTest, MatchesTheCrc16Mcrf4xxCheckValue) {
  static_assert(CrcAccumulate(std::string_view("123456789"), kCrcInit) == 0x6F91);
  const Bytes digits = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(CrcAccumulate(std::span<const std::uint8_t>(digits), kCrcInit), 0x6F91);
  EXPECT_EQ(CrcAccumulate(std::span<const std::uint8_t>(), kCrcInit), kCrcInit);
}

TEST(MavlinkFrameTest, ParsesAKnownHeartbeat) {
  const Parsed parsed = ParseWhole(kKnownHeartbeat);
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0], HeartbeatFrame(0xEF));
  EXPECT_EQ(parsed.counters, (ParserCounters{.frames_ok = 1}));
}

TEST(MavlinkFrameTest, EncodesKnownHeartbeatsByteForByte) {
  EXPECT_EQ(Encode(HeartbeatFrame(0xEF)), kKnownHeartbeat);
  Frame from_component_2 = HeartbeatFrame(0xEF);
  from_component_2.component_id = 2;
  EXPECT_EQ(Encode(from_component_2), kKnownHeartbeatComponent2);
}

TEST(MavlinkFrameTest, EncodesAndParsesAKnownTrimmedFrame) {
  Frame command;
  command.component_id = 50;
  command.message_id = kCommandLongId;
  command.payload_length = 33;
  const Bytes wire_payload(kKnownTrimmedCommandLong.begin() + kHeaderBytes,
                           kKnownTrimmedCommandLong.end() - kChecksumBytes);
  std::copy(wire_payload.begin(), wire_payload.end(), command.payload.begin());
  EXPECT_EQ(Encode(command), kKnownTrimmedCommandLong);

  const Parsed parsed = ParseWhole(kKnownTrimmedCommandLong);
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0].payload_length, 30);
  EXPECT_EQ(parsed.frames[0], AsReceived(command));
}

TEST(MavlinkFrameTest, AcceptsAKnownSignedFrameAndSkipsItsSignature) {
  // The signature's 0xFF bytes and the frame after it must not be scanned as part of the frame.
  const Parsed parsed = ParseWhole(Concat({kKnownSignedHeartbeat, kKnownHeartbeat}));
  ASSERT_EQ(parsed.frames.size(), 2u);
  Frame expected = HeartbeatFrame(0xEF);
  expected.component_id = 2;
  expected.incompat_flags = kIncompatSigned;
  EXPECT_EQ(parsed.frames[0], expected);
  EXPECT_EQ(parsed.frames[1], HeartbeatFrame(0xEF));
  EXPECT_EQ(parsed.counters, (ParserCounters{.frames_ok = 2, .signed_frames = 1}));
}

TEST(MavlinkFrameTest, SkipsASignatureThatLooksLikeFrames) {
  Bytes signed_frame = kKnownSignedHeartbeat;
  for (std::size_t i = signed_frame.size() - kSignatureBytes; i < signed_frame.size(); ++i) {
    signed_frame[i] = kStartV2;
  }
  const Parsed parsed = ParseWhole(Concat({signed_frame, kKnownHeartbeat}));
  EXPECT_EQ(parsed.frames.size(), 2u);
  EXPECT_EQ(parsed.counters, (ParserCounters{.frames_ok = 2, .signed_frames = 1}));
}

TEST(MavlinkFrameTest, SkipsAKnownV1FrameWhole) {
  const Bytes stream = Concat({kKnownV1Heartbeat, kKnownHeartbeat});
  for (const WireInfoLookup lookup : {&TestLookup, &EmptyLookup}) {
    const Parsed parsed = Parse(stream, stream.size(), false, lookup);
    if (lookup == &TestLookup) {
      ASSERT_EQ(parsed.frames.size(), 1u);
      EXPECT_EQ(parsed.frames[0], HeartbeatFrame(0xEF));
      EXPECT_EQ(parsed.counters, (ParserCounters{.frames_ok = 1, .v1_frames_skipped = 1}));
    } else {
      // Without CRC_EXTRA the v1 frame is trusted and skipped by its length byte; the v2 frame
      // cannot be checked at all.
      EXPECT_TRUE(parsed.frames.empty());
      EXPECT_EQ(parsed.counters, (ParserCounters{.bytes_skipped = kKnownHeartbeat.size() - 1,
                                                 .unknown_message_ids = 1,
                                                 .v1_frames_skipped = 1}));
    }
  }
}

TEST(MavlinkFrameTest, TreatsAV1FrameFailingItsChecksumAsGarbage) {
  Bytes damaged = kKnownV1Heartbeat;
  damaged[10] ^= 0x01;  // a payload byte
  ASSERT_FALSE(HasStartByteAfterFirst(damaged));
  const Parsed parsed = ParseWhole(Concat({damaged, kKnownHeartbeat}));
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.counters, (ParserCounters{.frames_ok = 1, .bytes_skipped = damaged.size()}));
}

TEST(MavlinkFrameTest, KeepsOneByteOfAnAllZeroPayload) {
  Frame zeros;
  zeros.message_id = kHilSensorId;
  zeros.payload_length = 65;
  const Bytes wire = Encode(zeros);
  ASSERT_EQ(wire.size(), kHeaderBytes + 1 + kChecksumBytes);
  EXPECT_EQ(wire[1], 1);
  EXPECT_EQ(wire[kHeaderBytes], 0);
  const Parsed parsed = ParseWhole(wire);
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0], AsReceived(zeros));
  EXPECT_EQ(parsed.frames[0].payload_length, 1);

  Frame empty = zeros;
  empty.payload_length = 0;
  EXPECT_EQ(Encode(empty), wire);
}

TEST(MavlinkFrameTest, TrimsTrailingZerosAndParsesThemBackAsZeros) {
  Frame frame = CountingSensorFrame(7);
  std::fill(frame.payload.begin() + 40, frame.payload.begin() + 65, 0);
  frame.payload[20] = 0;  // an inner zero stays
  const Bytes wire = Encode(frame);
  EXPECT_EQ(wire.size(), kHeaderBytes + 40 + kChecksumBytes);
  const Parsed parsed = ParseWhole(wire);
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0].payload_length, 40);
  EXPECT_EQ(parsed.frames[0].payload, frame.payload);
}

TEST(MavlinkFrameTest, TrimmedPayloadLengthNeverDropsTheFirstByte) {
  EXPECT_EQ(TrimmedPayloadLength({}), 1u);
  const Bytes zeros(9, 0);
  EXPECT_EQ(TrimmedPayloadLength(zeros), 1u);
  const Bytes tail = {0, 3, 0, 0};
  EXPECT_EQ(TrimmedPayloadLength(tail), 2u);
  const Bytes full = {1, 2, 3};
  EXPECT_EQ(TrimmedPayloadLength(full), 3u);
}

TEST(MavlinkFrameTest, EncoderRefusesWhatItCannotWrite) {
  const Frame frame = HeartbeatFrame(1);
  Bytes exact(kKnownHeartbeat.size());
  EXPECT_EQ(EncodeFrame(frame, 50, exact), exact.size());
  Bytes short_by_one(kKnownHeartbeat.size() - 1);
  EXPECT_EQ(EncodeFrame(frame, 50, short_by_one), 0u);

  Bytes out(kMaxFrameBytes);
  Frame signed_frame = frame;
  signed_frame.incompat_flags = kIncompatSigned;
  EXPECT_EQ(EncodeFrame(signed_frame, 50, out), 0u);
  Frame wide = frame;
  wide.message_id = kMaxMessageId + 1;
  EXPECT_EQ(EncodeFrame(wide, 50, out), 0u);
}

TEST(MavlinkFrameTest, ALargestFrameFitsTheStatedMaximum) {
  Frame frame;
  frame.message_id = 1;
  frame.payload_length = 255;
  frame.payload.fill(0x11);
  Bytes out(kMaxFrameBytes);
  EXPECT_EQ(EncodeFrame(frame, 0, out), kMaxFrameBytes);
  EXPECT_EQ(kMaxFrameBytes, 267u);
  EXPECT_EQ(kMaxSignedFrameBytes, 280u);
}

TEST(MavlinkFrameTest, CarriesAllThreeMessageIdBytes) {
  Frame frame;
  frame.message_id = kWideId;
  frame.payload_length = 40;
  frame.payload[0] = 9;
  const Bytes wire = Encode(frame);
  EXPECT_EQ(wire[7], 0x56);
  EXPECT_EQ(wire[8], 0x34);
  EXPECT_EQ(wire[9], 0x12);
  const Parsed parsed = ParseWhole(wire);
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0], AsReceived(frame));
}

Bytes MixedStream() {
  Frame wide;
  wide.message_id = kWideId;
  wide.payload_length = 40;
  wide.payload[39] = 0xFD;  // a start byte inside a frame is not a frame
  return Concat({kKnownHeartbeat, Encode(CountingSensorFrame(1)), kKnownSignedHeartbeat,
                 kKnownV1Heartbeat, kKnownTrimmedCommandLong, Encode(wide),
                 Encode(HeartbeatFrame(2))});
}

TEST(MavlinkFrameTest, ParsesTheSameWhateverTheChunking) {
  const Bytes stream = MixedStream();
  const Parsed whole = ParseWhole(stream);
  ASSERT_EQ(whole.frames.size(), 6u);
  EXPECT_EQ(whole.counters,
            (ParserCounters{.frames_ok = 6, .signed_frames = 1, .v1_frames_skipped = 1}));
  for (std::size_t chunk = 1; chunk <= stream.size(); ++chunk) {
    const Parsed chunked = Parse(stream, chunk);
    EXPECT_EQ(chunked.frames, whole.frames) << "chunk " << chunk;
    EXPECT_EQ(chunked.counters, whole.counters) << "chunk " << chunk;
  }
}

TEST(MavlinkFrameTest, ParsesTheSameWithIrregularChunks) {
  const Bytes stream = Concat({MixedStream(), MixedStream(), MixedStream()});
  const Parsed whole = ParseWhole(stream);
  std::mt19937 rng(1234);
  for (int trial = 0; trial < 50; ++trial) {
    FrameParser parser(&TestLookup);
    std::vector<Frame> frames;
    std::size_t at = 0;
    while (at < stream.size()) {
      const std::size_t n = std::min<std::size_t>(1 + rng() % 40, stream.size() - at);
      parser.Feed(std::span<const std::uint8_t>(stream).subspan(at, n),
                  [&](const Frame& frame) { frames.push_back(frame); });
      at += n;
    }
    EXPECT_EQ(frames, whole.frames);
    EXPECT_EQ(parser.counters(), whole.counters);
  }
}

TEST(MavlinkFrameTest, FeedsAnInputLargerThanItsBuffer) {
  Bytes stream;
  for (int i = 0; i < 100; ++i) {
    const Bytes frame = Encode(CountingSensorFrame(static_cast<std::uint8_t>(i)));
    stream.insert(stream.end(), frame.begin(), frame.end());
  }
  ASSERT_GT(stream.size(), FrameParser::kBufferBytes);
  const Parsed parsed = ParseWhole(stream);
  ASSERT_EQ(parsed.frames.size(), 100u);
  EXPECT_EQ(parsed.frames[99], CountingSensorFrame(99));
  EXPECT_EQ(parsed.counters, (ParserCounters{.frames_ok = 100}));
}

TEST(MavlinkFrameTest, PushTakesWhatFitsAndTheRestAfterNext) {
  FrameParser parser(&TestLookup);
  const Bytes big(FrameParser::kBufferBytes + 50, 0x00);
  EXPECT_EQ(parser.Push(big), FrameParser::kBufferBytes);
  EXPECT_EQ(parser.Push(big), 0u);
  EXPECT_FALSE(parser.Next().has_value());
  EXPECT_EQ(parser.buffered_bytes(), 0u);
  EXPECT_EQ(parser.Push(big), FrameParser::kBufferBytes);
  EXPECT_EQ(parser.counters().bytes_skipped, FrameParser::kBufferBytes);
}

TEST(MavlinkFrameTest, ResynchronisesAfterGarbage) {
  const Bytes garbage = {0x00, 0x11, 0x22, 0xFC, 0xFF, 0x7E, 0x55};
  const Parsed parsed =
      ParseWhole(Concat({garbage, kKnownHeartbeat, garbage, garbage, Encode(HeartbeatFrame(3))}));
  ASSERT_EQ(parsed.frames.size(), 2u);
  EXPECT_EQ(parsed.frames[0], HeartbeatFrame(0xEF));
  EXPECT_EQ(parsed.frames[1], HeartbeatFrame(3));
  EXPECT_EQ(parsed.counters, (ParserCounters{.frames_ok = 2, .bytes_skipped = 3 * garbage.size()}));
}

TEST(MavlinkFrameTest, FindsAFrameHiddenBehindAFalseStartByte) {
  // A false header (HEARTBEAT, 5 payload bytes) swallows the first 7 bytes of the real frame; its
  // checksum fails and the scan restarts right after the false start byte.
  const Bytes false_header = {0xFD, 0x05, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
  const Parsed parsed = ParseWhole(Concat({false_header, kKnownHeartbeat}));
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0], HeartbeatFrame(0xEF));
  EXPECT_EQ(parsed.counters,
            (ParserCounters{.frames_ok = 1, .bytes_skipped = 9, .crc_failures = 1}));
}

TEST(MavlinkFrameTest, FindsTheNextFrameAfterACorruptChecksum) {
  Bytes corrupt = kKnownHeartbeat;
  corrupt[19] ^= 0x01;
  ASSERT_FALSE(HasStartByteAfterFirst(corrupt));
  const Parsed parsed = ParseWhole(Concat({corrupt, Encode(HeartbeatFrame(4))}));
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0], HeartbeatFrame(4));
  EXPECT_EQ(
      parsed.counters,
      (ParserCounters{.frames_ok = 1, .bytes_skipped = corrupt.size() - 1, .crc_failures = 1}));
}

TEST(MavlinkFrameTest, FindsTheNextFrameAfterACorruptPayload) {
  Bytes corrupt = Encode(CountingSensorFrame(5));
  corrupt[30] ^= 0x80;
  ASSERT_FALSE(HasStartByteAfterFirst(corrupt));
  const Parsed parsed = ParseWhole(Concat({corrupt, kKnownHeartbeat}));
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0], HeartbeatFrame(0xEF));
  EXPECT_EQ(parsed.counters.crc_failures, 1u);
}

TEST(MavlinkFrameTest, FindsFramesBehindATruncatedFrame) {
  // The cut frame claims 77 bytes, so it takes in the start of the heartbeats behind it until its
  // checksum fails; the scan then restarts inside it and finds every heartbeat.
  const Bytes whole = Encode(CountingSensorFrame(6));
  const Bytes cut(whole.begin(), whole.begin() + 30);
  ASSERT_FALSE(HasStartByteAfterFirst(cut));
  const Bytes stream = Concat({cut, Encode(HeartbeatFrame(10)), Encode(HeartbeatFrame(11)),
                               Encode(HeartbeatFrame(12)), Encode(HeartbeatFrame(13))});
  const Parsed parsed = ParseWhole(stream);
  ASSERT_EQ(parsed.frames.size(), 4u);
  EXPECT_EQ(parsed.frames[0], HeartbeatFrame(10));
  EXPECT_EQ(parsed.frames[3], HeartbeatFrame(13));
  EXPECT_EQ(parsed.counters,
            (ParserCounters{.frames_ok = 4, .bytes_skipped = cut.size() - 1, .crc_failures = 1}));
}

TEST(MavlinkFrameTest, FinishGivesUpOnATruncatedFrameAtTheEnd) {
  // Too few bytes follow the cut frame to complete it: the heartbeat waits behind it until the
  // stream is declared ended.
  const Bytes whole = Encode(CountingSensorFrame(6));
  const Bytes cut(whole.begin(), whole.begin() + 30);
  const Bytes stream = Concat({cut, kKnownHeartbeat});
  EXPECT_TRUE(ParseWhole(stream).frames.empty());
  const Parsed parsed = ParseWhole(stream, /*finish=*/true);
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0], HeartbeatFrame(0xEF));
  EXPECT_EQ(
      parsed.counters,
      (ParserCounters{.frames_ok = 1, .bytes_skipped = cut.size() - 1, .truncated_frames = 1}));
}

TEST(MavlinkFrameTest, FinishCountsATruncatedHeader) {
  const Bytes stream = {0x01, 0xFD, 0x09, 0x00};
  const Parsed parsed = ParseWhole(stream, /*finish=*/true);
  EXPECT_TRUE(parsed.frames.empty());
  EXPECT_EQ(parsed.counters, (ParserCounters{.bytes_skipped = 3, .truncated_frames = 1}));
}

TEST(MavlinkFrameTest, PushAfterFinishStartsWaitingAgain) {
  FrameParser parser(&TestLookup);
  parser.Finish();
  const std::span<const std::uint8_t> heartbeat(kKnownHeartbeat);
  parser.Push(heartbeat.first(12));
  EXPECT_FALSE(parser.Next().has_value());
  EXPECT_EQ(parser.counters().truncated_frames, 0u);
  parser.Push(heartbeat.subspan(12));
  EXPECT_TRUE(parser.Next().has_value());
}

TEST(MavlinkFrameTest, DropsAnUnknownMessageId) {
  Frame unknown = HeartbeatFrame(8);
  unknown.message_id = 1234;
  Bytes wire(kMaxFrameBytes);
  wire.resize(EncodeFrame(unknown, 0x33, wire));
  ASSERT_FALSE(HasStartByteAfterFirst(wire));
  const Parsed parsed = ParseWhole(Concat({wire, kKnownHeartbeat}));
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.frames[0], HeartbeatFrame(0xEF));
  EXPECT_EQ(
      parsed.counters,
      (ParserCounters{.frames_ok = 1, .bytes_skipped = wire.size() - 1, .unknown_message_ids = 1}));
}

TEST(MavlinkFrameTest, DropsAPayloadLongerThanTheMessage) {
  Frame too_long = HeartbeatFrame(9);
  too_long.payload_length = 10;  // HEARTBEAT has 9
  too_long.payload[9] = 0x42;
  const Bytes wire = Encode(too_long);
  ASSERT_EQ(wire[1], 10);
  ASSERT_FALSE(HasStartByteAfterFirst(wire));
  const Parsed parsed = ParseWhole(Concat({wire, kKnownHeartbeat}));
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.counters,
            (ParserCounters{.frames_ok = 1, .bytes_skipped = wire.size() - 1, .bad_lengths = 1}));
}

TEST(MavlinkFrameTest, DropsAFrameWithAnUnknownIncompatFlag) {
  Bytes wire = kKnownHeartbeat;
  wire[2] = 0x02;
  const Parsed parsed = ParseWhole(Concat({wire, kKnownHeartbeat}));
  ASSERT_EQ(parsed.frames.size(), 1u);
  EXPECT_EQ(parsed.counters, (ParserCounters{.frames_ok = 1,
                                             .bytes_skipped = wire.size() - 1,
                                             .unsupported_incompat_flags = 1}));
}

TEST(MavlinkFrameTest, ZeroExtendsEveryParsedPayload) {
  // A long frame first, so stale bytes would show if the parser reused them.
  Frame short_frame = CountingSensorFrame(1);
  std::fill(short_frame.payload.begin() + 3, short_frame.payload.end(), 0);
  const Parsed parsed = ParseWhole(Concat({Encode(CountingSensorFrame(0)), Encode(short_frame)}));
  ASSERT_EQ(parsed.frames.size(), 2u);
  EXPECT_EQ(parsed.frames[1].payload_length, 3);
  EXPECT_TRUE(std::all_of(parsed.frames[1].payload.begin() + 3, parsed.frames[1].payload.end(),
                          [](std::uint8_t b) { return b == 0; }));
}

TEST(MavlinkFrameTest, CountsNoMoreEventsThanBytesOnRandomInput) {
  std::mt19937 rng(99);
  Bytes noise(20000);
  for (std::uint8_t& byte : noise) {
    // Plenty of start bytes, so every path runs.
    byte = rng() % 4 == 0 ? (rng() % 2 ? kStartV2 : kStartV1) : static_cast<std::uint8_t>(rng());
  }
  const Parsed parsed = ParseWhole(Concat({noise, kKnownHeartbeat}), /*finish=*/true);
  const ParserCounters& c = parsed.counters;
  const std::uint64_t events =
      c.frames_ok + c.bytes_skipped + c.crc_failures + c.unknown_message_ids + c.bad_lengths +
      c.unsupported_incompat_flags + c.v1_frames_skipped + c.truncated_frames;
  EXPECT_LE(events, noise.size() + kKnownHeartbeat.size());
  EXPECT_EQ(c.frames_ok, parsed.frames.size());
  EXPECT_GE(c.frames_ok, 1u);
}

TEST(MavlinkFrameTest, ReadsTheFrameSizeFromItsHeader) {
  EXPECT_EQ(FrameSizeFromHeader(kKnownHeartbeat), kKnownHeartbeat.size());
  EXPECT_EQ(FrameSizeFromHeader(kKnownSignedHeartbeat), kKnownSignedHeartbeat.size());
  EXPECT_EQ(FrameSizeFromHeader(kKnownV1Heartbeat), kKnownV1Heartbeat.size());
  const Bytes two = {0xFD, 0x09};
  EXPECT_EQ(FrameSizeFromHeader(two), std::nullopt);
  const Bytes other = {0x00, 0x09, 0x00};
  EXPECT_EQ(FrameSizeFromHeader(other), std::nullopt);
}

}  // namespace
}  // namespace hilrig::mavlink
