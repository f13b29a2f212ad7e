#include "rig/tactile_protocol.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "dut_fw/sensor_node.h"

namespace hilrig::rig {
namespace {

TactileSample Sample() {
  return {.node_id = 3,
          .code = {0x04B0, 0xFFFD, 0x8000},
          .sequence = 250,
          .status = tactile_bus::kSampleStale};
}

TactileStatus Status() {
  return {.node_id = 7,
          .temperature_centi_c = -1234,
          .flags = tactile_bus::kFlagConfigPending,
          .gain_sel = 5,
          .resolution = 2,
          .rate_code = 5,
          .rx_error_count = 9,
          .firmware_version = 0x10};
}

std::vector<std::uint8_t> Bytes(const CanFrame& frame) {
  return {frame.payload().begin(), frame.payload().end()};
}

template <typename T>
void ExpectRejected(const Result<T>& decoded, const std::string& complaint) {
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().message.find(complaint), std::string::npos) << decoded.error().message;
}

CanFrame RawFrame(std::uint32_t id, std::vector<std::uint8_t> bytes) {
  return CanFrame::Classic(id, bytes);
}

TEST(TactileProtocolTest, SampleLayoutIsLittleEndianThenSequenceAndStatus) {
  const CanFrame frame = EncodeTactileSample(Sample());

  EXPECT_EQ(frame.id, 0x103u);
  EXPECT_EQ(Bytes(frame), (std::vector<std::uint8_t>{0xB0, 0x04, 0xFD, 0xFF, 0x00, 0x80, 250, 4}));
}

TEST(TactileProtocolTest, SampleRoundTrips) {
  const Result<TactileSample> decoded = DecodeTactileSample(EncodeTactileSample(Sample()));

  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded.value(), Sample());
}

TEST(TactileProtocolTest, StatusLayoutPutsTemperatureFirst) {
  const CanFrame frame = EncodeTactileStatus(Status());

  EXPECT_EQ(frame.id, 0x187u);
  // -1234 = 0xFB2E.
  EXPECT_EQ(Bytes(frame), (std::vector<std::uint8_t>{0x2E, 0xFB, 0x02, 5, 2, 5, 9, 0x10}));
}

TEST(TactileProtocolTest, StatusRoundTrips) {
  const Result<TactileStatus> decoded = DecodeTactileStatus(EncodeTactileStatus(Status()));

  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded.value(), Status());
}

TEST(TactileProtocolTest, SetRateCommandCarriesHzLittleEndianInEightBytes) {
  const CanFrame frame =
      EncodeTactileConfig({.node_id = 2, .command = TactileCommand::kSetRate, .rate_hz = 1000});

  EXPECT_EQ(frame.id, 0x082u);
  EXPECT_EQ(Bytes(frame), (std::vector<std::uint8_t>{1, 0xE8, 0x03, 0, 0, 0, 0, 0}));
}

TEST(TactileProtocolTest, EveryCommandRoundTrips) {
  const std::vector<TactileConfigCommand> commands = {
      {.node_id = 0, .command = TactileCommand::kSetRate, .rate_hz = 50},
      {.node_id = 1, .command = TactileCommand::kSetGain, .gain_sel = 7},
      {.node_id = 6, .command = TactileCommand::kSetResolution, .resolution = 3},
      {.node_id = 7, .command = TactileCommand::kZero},
      {.node_id = 0, .command = TactileCommand::kReset},
  };

  for (const TactileConfigCommand& command : commands) {
    const Result<TactileConfigCommand> decoded = DecodeTactileConfig(EncodeTactileConfig(command));

    ASSERT_TRUE(decoded.ok()) << decoded.error().message;
    EXPECT_EQ(decoded.value(), command);
  }
}

TEST(TactileProtocolTest, ShortestConfigFramesAreAccepted) {
  const Result<TactileConfigCommand> zero = DecodeTactileConfig(RawFrame(0x085, {4, 0}));
  const Result<TactileConfigCommand> rate = DecodeTactileConfig(RawFrame(0x080, {1, 10, 0}));

  ASSERT_TRUE(zero.ok()) << zero.error().message;
  EXPECT_EQ(zero.value().command, TactileCommand::kZero);
  EXPECT_EQ(zero.value().node_id, 5);
  ASSERT_TRUE(rate.ok()) << rate.error().message;
  EXPECT_EQ(rate.value().rate_hz, 10);
  EXPECT_EQ(rate.value().node_id, tactile_bus::kBroadcastNodeId);
}

TEST(TactileProtocolTest, ClassifyByIdRange) {
  EXPECT_EQ(Classify(RawFrame(0x080, {})), TactileFrameKind::kConfig);
  EXPECT_EQ(Classify(RawFrame(0x087, {})), TactileFrameKind::kConfig);
  EXPECT_EQ(Classify(RawFrame(0x088, {})), TactileFrameKind::kUnknownId);
  EXPECT_EQ(Classify(RawFrame(0x100, {})), TactileFrameKind::kUnknownId);
  EXPECT_EQ(Classify(RawFrame(0x101, {})), TactileFrameKind::kSample);
  EXPECT_EQ(Classify(RawFrame(0x107, {})), TactileFrameKind::kSample);
  EXPECT_EQ(Classify(RawFrame(0x180, {})), TactileFrameKind::kUnknownId);
  EXPECT_EQ(Classify(RawFrame(0x181, {})), TactileFrameKind::kStatus);
  EXPECT_EQ(Classify(RawFrame(0x188, {})), TactileFrameKind::kUnknownId);
  EXPECT_EQ(Classify(CanFrame::ClassicExtended(0x101, {})), TactileFrameKind::kNotClassicData);
  EXPECT_EQ(Classify(CanFrame::Remote(0x101, 8, false)), TactileFrameKind::kNotClassicData);
  EXPECT_EQ(Classify(CanFrame::Fd(0x101, {}, false)), TactileFrameKind::kNotClassicData);
  EXPECT_EQ(Classify(CanFrame::ErrorFrame(0x101, {})), TactileFrameKind::kNotClassicData);
}

TEST(TactileProtocolTest, NodeOfGivesTheAddressedNode) {
  EXPECT_EQ(TactileNodeOf(RawFrame(0x080, {})), std::optional<std::uint8_t>(0));
  EXPECT_EQ(TactileNodeOf(RawFrame(0x104, {})), std::optional<std::uint8_t>(4));
  EXPECT_EQ(TactileNodeOf(RawFrame(0x187, {})), std::optional<std::uint8_t>(7));
  EXPECT_EQ(TactileNodeOf(RawFrame(0x200, {})), std::nullopt);
}

TEST(TactileProtocolTest, DecodeWithTheKindGivenMatchesTheClassifyingDecode) {
  const CanFrame sample = RawFrame(0x103, {1, 2, 3, 4, 5, 6, 7, 8});
  const CanFrame short_status = RawFrame(0x183, {1});

  const Result<TactileMessage> decoded = DecodeTactileFrame(sample, TactileFrameKind::kSample);
  const Result<TactileMessage> rejected =
      DecodeTactileFrame(short_status, TactileFrameKind::kStatus);

  ASSERT_TRUE(decoded.ok());
  const auto* decoded_sample = std::get_if<TactileSample>(&decoded.value());
  ASSERT_NE(decoded_sample, nullptr);
  EXPECT_EQ(decoded_sample->node_id, 3);
  EXPECT_EQ(decoded_sample->code, (std::array<std::uint16_t, 3>{0x0201, 0x0403, 0x0605}));
  EXPECT_EQ(decoded_sample->sequence, 7);
  EXPECT_EQ(decoded_sample->status, 8);
  ExpectRejected(rejected, "expected 8 bytes, got 1");
  EXPECT_EQ(TactileNodeOf(sample, TactileFrameKind::kSample), std::optional<std::uint8_t>(3));
  EXPECT_EQ(TactileNodeOf(RawFrame(0x300, {}), TactileFrameKind::kUnknownId), std::nullopt);
}

TEST(TactileProtocolTest, RejectsSampleOfWrongLength) {
  ExpectRejected(DecodeTactileSample(RawFrame(0x103, {1, 2, 3, 4, 5, 6, 7})),
                 "tactile sample 0x103: expected 8 bytes, got 7");
}

TEST(TactileProtocolTest, RejectsStatusOfWrongLength) {
  ExpectRejected(DecodeTactileStatus(RawFrame(0x183, {1})), "expected 8 bytes, got 1");
}

TEST(TactileProtocolTest, RejectsSampleWithAnotherKindsId) {
  ExpectRejected(DecodeTactileSample(EncodeTactileStatus(Status())),
                 "tactile sample: id 0x187 is outside the sample ids 0x101..0x107");
}

TEST(TactileProtocolTest, RejectsFramesThatAreNotClassicData) {
  ExpectRejected(DecodeTactileSample(CanFrame::ClassicExtended(0x103, {})), "extended");
  ExpectRejected(DecodeTactileSample(CanFrame::Remote(0x103, 8, false)), "remote");
  ExpectRejected(DecodeTactileStatus(CanFrame::Fd(0x183, std::vector<std::uint8_t>(8), false)),
                 "CAN FD");
  ExpectRejected(DecodeTactileFrame(CanFrame::ErrorFrame(0x4, {})), "error frame");
}

TEST(TactileProtocolTest, RejectsUnknownId) {
  ExpectRejected(DecodeTactileFrame(RawFrame(0x300, {})), "0x300: id is not a tactile id");
}

TEST(TactileProtocolTest, RejectsBadCommands) {
  ExpectRejected(DecodeTactileConfig(RawFrame(0x081, {4})), "expected 2..8 bytes, got 1");
  ExpectRejected(DecodeTactileConfig(RawFrame(0x081, {9, 0})), "command 9 is unknown");
  ExpectRejected(DecodeTactileConfig(RawFrame(0x081, {0, 0})), "command 0 is unknown");
  ExpectRejected(DecodeTactileConfig(RawFrame(0x081, {1, 50})), "set-rate needs 3 bytes, got 2");
  ExpectRejected(DecodeTactileConfig(RawFrame(0x081, {1, 33, 0})), "rate 33 Hz is not supported");
  ExpectRejected(DecodeTactileConfig(RawFrame(0x081, {2, 8})), "gain_sel 8 is not 0..7");
  ExpectRejected(DecodeTactileConfig(RawFrame(0x081, {3, 4})), "resolution 4 is not 0..3");
}

TEST(TactileProtocolTest, DecodeNeverReadsPastTheDataForAnyLength) {
  // A corrupt in-memory frame with a length beyond the CAN limits is rejected, not trusted.
  CanFrame frame = EncodeTactileSample(Sample());
  frame.length = 200;

  ExpectRejected(DecodeTactileFrame(frame), "expected 8 bytes, got 200");
}

TEST(TactileProtocolTest, RateTableMapsBothWays) {
  for (std::uint8_t code = 0; code < tactile_bus::kRateHzByCode.size(); ++code) {
    const std::optional<std::uint16_t> rate_hz = TactileRateHzFromCode(code);
    ASSERT_TRUE(rate_hz.has_value());
    EXPECT_EQ(TactileRateCodeFromHz(*rate_hz), code);
  }
  EXPECT_EQ(TactileRateHzFromCode(11), std::nullopt);
  EXPECT_EQ(TactileRateCodeFromHz(51), std::nullopt);
}

TEST(TactileProtocolTest, PriorityOrderIsConfigThenSamplesThenStatus) {
  const CanFrame config = EncodeTactileConfig({.node_id = 7, .command = TactileCommand::kZero});
  TactileSample sample = Sample();
  sample.node_id = 7;
  const CanFrame sample_frame = EncodeTactileSample(sample);
  TactileStatus status = Status();
  status.node_id = 1;

  EXPECT_LT(config.id, sample_frame.id);
  EXPECT_LT(sample_frame.id, EncodeTactileStatus(status).id);
}

TEST(TactileProtocolTest, SevenNodesAtFiftyHertzLoadAOneMegabitBusUnderFivePercent) {
  // Worst-case bit stuffing, as CountFrameBits counts it.
  const std::int64_t sample_bits = CountFrameBits(EncodeTactileSample(Sample())).nominal_bits;
  const std::int64_t status_bits = CountFrameBits(EncodeTactileStatus(Status())).nominal_bits;

  const double load = (7.0 * 50.0 * double(sample_bits) + 7.0 * 1.0 * double(status_bits)) / 1e6;

  EXPECT_EQ(sample_bits, 135);  // the figure quoted in proto/TACTILE_PROTOCOL.md
  EXPECT_LT(load, 0.05);
}

// The node firmware and the rig codec are two statements of one layout: what the node sends, the
// codec must read back field for field, and what the codec sends, the node must obey.
CanFrame ToCanFrame(const dut_fw::NodeFrame& frame) {
  return CanFrame::Classic(frame.id, std::span<const std::uint8_t>(frame.data.data(), frame.len));
}

dut_fw::NodeFrame ToNodeFrame(const CanFrame& frame) {
  dut_fw::NodeFrame node_frame;
  node_frame.id = static_cast<std::uint16_t>(frame.id);
  node_frame.len = frame.length;
  std::copy_n(frame.data.begin(), frame.length, node_frame.data.begin());
  return node_frame;
}

TEST(TactileProtocolTest, NodeFirmwareSampleFrameDecodesWithTheRigCodec) {
  dut_fw::SensorNode<> node(4, 0);
  node.TakeSample(0, dut_fw::ChipConversion{.code = {1, 2, 3}});

  const dut_fw::NodeFrame frame =
      node.TakeSample(20'000'000, dut_fw::ChipConversion{.code = {0x1234, 0x7FFF, 0xFFFF}});
  const Result<TactileSample> decoded = DecodeTactileSample(ToCanFrame(frame));

  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded.value(), (TactileSample{.node_id = 4,
                                            .code = {0x1234, 0x7FFF, 0xFFFF},
                                            .sequence = 1,
                                            .status = tactile_bus::kSampleSaturated}));
}

TEST(TactileProtocolTest, NodeFirmwareObeysRigCommandsAndAnswersInRigFormat) {
  dut_fw::SensorNode<> node(2, 0);
  node.OnTemperature(3105);

  const std::optional<dut_fw::NodeFrame> answer = node.OnBusFrame(
      ToNodeFrame(
          EncodeTactileConfig({.node_id = 2, .command = TactileCommand::kSetRate, .rate_hz = 100})),
      0);
  ASSERT_TRUE(answer.has_value());
  const Result<TactileStatus> status = DecodeTactileStatus(ToCanFrame(*answer));

  ASSERT_TRUE(status.ok()) << status.error().message;
  EXPECT_EQ(status.value(), (TactileStatus{.node_id = 2,
                                           .temperature_centi_c = 3105,
                                           .flags = 0,
                                           .gain_sel = 7,
                                           .resolution = 0,
                                           .rate_code = *TactileRateCodeFromHz(100),
                                           .rx_error_count = 0,
                                           .firmware_version = 0x10}));
  EXPECT_EQ(node.rate_hz(), 100);
}

}  // namespace
}  // namespace hilrig::rig
