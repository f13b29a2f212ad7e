// The HIL link on a byte stream: messages framed with COBS and a CRC-16 cross an in-memory stream
// whole, and garbage, a flipped byte, a lost byte or an oversize frame cost the frame they hit and
// nothing after it, each counted by name.
#include "host/link/line_link.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host/link/memory_byte_stream.h"

namespace hilrig::host {
namespace {

proto::LinkMessage Step(std::uint64_t tick) {
  proto::LinkMessage message;
  message.mutable_serial_step()->set_tick(tick);
  message.mutable_serial_step()->set_bridge_bytes(0x1234);
  return message;
}

struct Line {
  std::unique_ptr<MemoryByteStream> a;
  std::unique_ptr<MemoryByteStream> b;
  Line() { std::tie(a, b) = MakeMemoryStreamPair(); }
};

// The bytes one frame of `message` takes on the line.
std::vector<std::uint8_t> FrameBytes(const proto::LinkMessage& message) {
  auto [a, b] = MakeMemoryStreamPair();
  LineLink link(*a);
  EXPECT_TRUE(link.Send(message, 0));
  std::vector<std::uint8_t> bytes(4096);
  const StreamRead read = b->ReadSome(bytes, 0);
  bytes.resize(read.bytes);
  return bytes;
}

std::uint64_t Received(LineLink& link) {
  const LineReceived received = link.Receive(0);
  EXPECT_EQ(received.status, LineReceiveStatus::kMessage) << received.error;
  return received.message.serial_step().tick();
}

TEST(LineLinkTest, CarriesMessagesWholeAndCountsBytes) {
  Line line;
  LineLink sender(*line.a);
  LineLink receiver(*line.b);
  ASSERT_TRUE(sender.Send(Step(1), 0));
  ASSERT_TRUE(sender.Send(Step(2), 0, /*flush_first=*/true));
  EXPECT_EQ(Received(receiver), 1u);
  EXPECT_EQ(Received(receiver), 2u);
  EXPECT_EQ(receiver.Receive(0).status, LineReceiveStatus::kTimeout);
  EXPECT_EQ(sender.counters().frames_sent, 2u);
  EXPECT_EQ(sender.counters().bytes_sent, line.a->bytes_written());
  EXPECT_EQ(receiver.counters().bytes_received, line.a->bytes_written());
  EXPECT_EQ(receiver.counters().frames_received, 2u);
  EXPECT_EQ(receiver.counters().bad_checksum + receiver.counters().malformed, 0u);
}

TEST(LineLinkTest, RidesThroughGarbageFlippedAndLostBytes) {
  Line line;
  LineLink receiver(*line.b);
  std::vector<std::uint8_t> wire = {0x17, 0x42, 0x00};  // garbage ended by a delimiter
  std::vector<std::uint8_t> flipped = FrameBytes(Step(1));
  flipped[2] ^= 0x10;  // inside the payload: the CRC catches it
  std::vector<std::uint8_t> lost = FrameBytes(Step(2));
  lost.erase(lost.begin() + 3);
  for (const auto& part : {flipped, lost, FrameBytes(Step(3))}) {
    wire.insert(wire.end(), part.begin(), part.end());
  }
  ASSERT_TRUE(line.a->WriteAll(wire, 0));
  EXPECT_EQ(Received(receiver), 3u);
  // The garbage and the shortened frame are bad COBS; the flipped byte fails the CRC.
  const LineLinkCounters& counters = receiver.counters();
  EXPECT_EQ(counters.bad_checksum + counters.malformed, 3u);
  EXPECT_GE(counters.bad_checksum, 1u);
  EXPECT_EQ(counters.frames_received, 1u);
}

TEST(LineLinkTest, CountsAFrameThatIsNoMessageAndAnOversizeOne) {
  Line line;
  LineLink receiver(*line.b);
  // A CRC-valid frame whose payload does not parse (a field with wire type 7).
  std::vector<std::uint8_t> junk_payload = {0x0F, 0x01};
  std::vector<std::uint8_t> junk(dut_link::EncodedFrameBytes(junk_payload.size()));
  junk.resize(dut_link::EncodeFrame(junk_payload, junk));
  std::vector<std::uint8_t> oversize(dut_link::kMaxLineMessageBytes + 100, 0x01);
  oversize.push_back(0x00);
  ASSERT_TRUE(line.a->WriteAll(junk, 0));
  ASSERT_TRUE(line.a->WriteAll(oversize, 0));
  ASSERT_TRUE(line.a->WriteAll(FrameBytes(Step(7)), 0));
  EXPECT_EQ(Received(receiver), 7u);
  EXPECT_EQ(receiver.counters().malformed, 1u);
  EXPECT_EQ(receiver.counters().oversize, 1u);
}

TEST(LineLinkTest, RefusesAMessageOverTheLimitAndReportsTheClose) {
  Line line;
  LineLink sender(*line.a);
  proto::LinkMessage big;
  big.mutable_hello()->set_name(std::string(dut_link::kMaxLineMessageBytes, 'x'));
  const rig::Result<void> sent = sender.Send(big, 0);
  ASSERT_FALSE(sent);
  EXPECT_NE(sent.error().message.find("limit"), std::string::npos);
  ASSERT_TRUE(sender.Send(Step(4), 0));
  line.a->Close();
  LineLink receiver(*line.b);
  EXPECT_EQ(Received(receiver), 4u);  // what was sent before the close still arrives
  EXPECT_EQ(receiver.Receive(0).status, LineReceiveStatus::kClosed);
}

}  // namespace
}  // namespace hilrig::host
