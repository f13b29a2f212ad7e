#include "dut_fw/sensor_node.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

namespace hilrig::dut_fw {
namespace {

namespace np = tactile_bus;

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSecond = 1'000'000'000;

ChipConversion Conversion(std::uint16_t x, std::uint16_t y, std::uint16_t z, bool error = false) {
  return ChipConversion{.code = {x, y, z}, .error = error};
}

std::array<std::uint16_t, 3> Codes(const NodeFrame& frame) {
  return {std::uint16_t(frame.data[0] | frame.data[1] << 8),
          std::uint16_t(frame.data[2] | frame.data[3] << 8),
          std::uint16_t(frame.data[4] | frame.data[5] << 8)};
}

std::uint8_t Sequence(const NodeFrame& frame) { return frame.data[6]; }
std::uint8_t SampleStatus(const NodeFrame& frame) { return frame.data[7]; }
std::uint8_t StatusFlags(const NodeFrame& frame) { return frame.data[2]; }

NodeFrame Command(std::uint16_t id, std::vector<std::uint8_t> bytes) {
  NodeFrame frame;
  frame.id = id;
  frame.len = std::uint8_t(bytes.size());
  std::copy(bytes.begin(), bytes.end(), frame.data.begin());
  return frame;
}

// Runs the node's main loop every `step_ns` until `end_ns`, with a chip that always answers, and
// returns the times at which samples were taken.
template <std::size_t N>
std::vector<std::int64_t> SampleTimes(SensorNode<N>& node, std::int64_t start_ns,
                                      std::int64_t end_ns, std::int64_t step_ns) {
  std::vector<std::int64_t> times;
  for (std::int64_t now = start_ns; now < end_ns; now += step_ns) {
    if (!node.SampleDue(now)) continue;
    node.TakeSample(now, Conversion(0, 0, 0));
    times.push_back(now);
  }
  return times;
}

// ---- sampling schedule ----------------------------------------------------------------------

TEST(SampleScheduleTest, FiftyHertzSlotsAreExactTwentyMillisecondMultiples) {
  SampleSchedule schedule;
  schedule.Start(50, 7 * kMs);

  std::vector<std::int64_t> due;
  for (int slot = 0; slot < 5000; ++slot) {  // 100 s
    due.push_back(schedule.NextDueNs());
    ASSERT_EQ(schedule.Consume(schedule.NextDueNs()), 1u);
  }

  for (int slot = 0; slot < 5000; ++slot) {
    ASSERT_EQ(due[slot], 7 * kMs + slot * 20 * kMs) << slot;
  }
}

TEST(SampleScheduleTest, RateThatDoesNotDivideASecondDoesNotDrift) {
  SampleSchedule schedule;
  schedule.Start(3, 0);

  for (int slot = 0; slot < 3000; ++slot) schedule.Consume(schedule.NextDueNs());

  EXPECT_EQ(schedule.NextDueNs(), 1000 * kSecond);
}

TEST(SampleScheduleTest, ZeroHertzNeverFallsDue) {
  SampleSchedule schedule;
  schedule.Start(0, 0);

  EXPECT_FALSE(schedule.Due(1000 * kSecond));
  EXPECT_EQ(schedule.Consume(1000 * kSecond), 0u);
}

TEST(SensorNodeTest, SamplesAtFiftyHertzExactlyFromAOneMillisecondLoop) {
  SensorNode<> node(1, 0);

  const std::vector<std::int64_t> times = SampleTimes(node, 0, 10 * kSecond, kMs);

  ASSERT_EQ(times.size(), 500u);
  for (std::size_t k = 0; k < times.size(); ++k) EXPECT_EQ(times[k], std::int64_t(k) * 20 * kMs);
  EXPECT_EQ(node.skipped_slots(), 0u);
}

TEST(SensorNodeTest, LateLoopSkipsSlotsAndAdvancesTheSequenceOverThem) {
  SensorNode<> node(1, 0);
  ASSERT_EQ(Sequence(node.TakeSample(0, Conversion(0, 0, 0))), 0);

  // 65 ms late: the slots at 20, 40 and 60 ms are due at once; one frame goes out.
  const NodeFrame frame = node.TakeSample(65 * kMs, Conversion(0, 0, 0));

  EXPECT_EQ(Sequence(frame), 3);
  EXPECT_EQ(node.skipped_slots(), 2u);
  EXPECT_FALSE(node.SampleDue(79 * kMs));
  EXPECT_TRUE(node.SampleDue(80 * kMs));
}

// ---- packing ---------------------------------------------------------------------------------

TEST(SensorNodeTest, SampleFrameCarriesChipWordsLittleEndian) {
  SensorNode<> node(3, 0);

  const NodeFrame frame = node.TakeSample(0, Conversion(0x1234, 0xABCD, 0x00FF));

  EXPECT_EQ(frame.id, 0x103);
  EXPECT_EQ(frame.len, 8);
  EXPECT_EQ(frame.data, (std::array<std::uint8_t, 8>{0x34, 0x12, 0xCD, 0xAB, 0xFF, 0x00, 0, 0}));
}

TEST(SensorNodeTest, SequenceWrapsAfter255) {
  SensorNode<> node(2, 0);

  std::vector<std::uint8_t> sequences;
  for (int i = 0; i < 300; ++i) {
    sequences.push_back(Sequence(node.TakeSample(i * 20 * kMs, Conversion(0, 0, 0))));
  }

  for (int i = 0; i < 300; ++i) EXPECT_EQ(sequences[i], std::uint8_t(i % 256)) << i;
}

TEST(SensorNodeTest, MissedConversionResendsLastResultMarkedStale) {
  SensorNode<> node(4, 0);
  node.TakeSample(0, Conversion(10, 20, 30));

  const NodeFrame stale = node.TakeSample(20 * kMs, std::nullopt);
  const NodeFrame status = node.TakeStatus(20 * kMs);

  EXPECT_EQ(Codes(stale), (std::array<std::uint16_t, 3>{10, 20, 30}));
  EXPECT_EQ(SampleStatus(stale), np::kSampleStale);
  EXPECT_EQ(Sequence(stale), 1);
  EXPECT_EQ(StatusFlags(status) & np::kFlagChipError, np::kFlagChipError);
}

TEST(SensorNodeTest, FreshConversionClearsStaleAndChipError) {
  SensorNode<> node(4, 0);
  node.TakeSample(0, std::nullopt);

  const NodeFrame fresh = node.TakeSample(20 * kMs, Conversion(1, 2, 3));

  EXPECT_EQ(SampleStatus(fresh), 0);
  EXPECT_EQ(StatusFlags(node.TakeStatus(20 * kMs)) & np::kFlagChipError, 0);
}

TEST(SensorNodeTest, ChipErrorBitIsForwardedAndTheResultIsNotReusedWhenStale) {
  SensorNode<> node(4, 0);
  node.TakeSample(0, Conversion(10, 20, 30));

  const NodeFrame errored = node.TakeSample(20 * kMs, Conversion(99, 99, 99, /*error=*/true));
  const NodeFrame stale = node.TakeSample(40 * kMs, std::nullopt);

  EXPECT_EQ(SampleStatus(errored), np::kSampleConversionError);
  EXPECT_EQ(Codes(errored), (std::array<std::uint16_t, 3>{99, 99, 99}));
  EXPECT_EQ(Codes(stale), (std::array<std::uint16_t, 3>{10, 20, 30}));
}

TEST(SensorNodeTest, RailCodeIsMarkedSaturatedForTheAppliedResolution) {
  SensorNode<> node(5, 0);

  // RES 0 is two's complement: 0x7FFF is the positive rail.
  const NodeFrame frame = node.TakeSample(0, Conversion(0, 0x7FFF, 0));

  EXPECT_EQ(SampleStatus(frame), np::kSampleSaturated);
}

TEST(SensorNodeTest, ChipTemperatureWordConvertsToCentiDegrees) {
  EXPECT_EQ(ChipTemperatureCentiC(46244), 2500);
  EXPECT_EQ(ChipTemperatureCentiC(46244 + 452), 3500);
  EXPECT_EQ(ChipTemperatureCentiC(46244 - 452), 1500);
}

// ---- status and commands ----------------------------------------------------------------------

TEST(SensorNodeTest, StatusFrameGoesOutOncePerSecond) {
  SensorNode<> node(6, 0);

  int statuses = 0;
  for (std::int64_t now = 0; now < 10 * kSecond; now += kMs) {
    if (node.StatusDue(now)) {
      const NodeFrame frame = node.TakeStatus(now);
      EXPECT_EQ(frame.id, 0x186);
      EXPECT_EQ(now, statuses * kSecond);
      ++statuses;
    }
  }

  EXPECT_EQ(statuses, 10);
}

TEST(SensorNodeTest, StatusFrameLayout) {
  SensorNode<> node(6, 0);
  node.OnTemperature(-1234);

  const NodeFrame frame = node.TakeStatus(0);

  EXPECT_EQ(frame.len, 8);
  // -1234 = 0xFB2E; gain 7, res 0, rate code 5 (50 Hz), no rx errors, firmware 1.0.
  EXPECT_EQ(frame.data, (std::array<std::uint8_t, 8>{0x2E, 0xFB, 0, 7, 0, 5, 0, 0x10}));
}

TEST(SensorNodeTest, SetRateCommandChangesScheduleAndAnswersWithStatus) {
  SensorNode<> node(1, 0);
  node.TakeSample(0, Conversion(0, 0, 0));

  const std::optional<NodeFrame> answer =
      node.OnBusFrame(Command(0x081, {np::kCommandSetRate, 100, 0}), 5 * kMs);
  const std::vector<std::int64_t> times = SampleTimes(node, 5 * kMs, 40 * kMs, kMs);

  ASSERT_TRUE(answer.has_value());
  EXPECT_EQ(answer->id, 0x181);
  EXPECT_EQ(answer->data[5], *RateCodeFromHz(100));
  EXPECT_EQ(node.rate_hz(), 100);
  EXPECT_EQ(times, (std::vector<std::int64_t>{5 * kMs, 15 * kMs, 25 * kMs, 35 * kMs}));
}

TEST(SensorNodeTest, SetGainIsPendingUntilTheChipIsProgrammed) {
  SensorNode<> node(1, 0);

  const std::optional<NodeFrame> answer =
      node.OnBusFrame(Command(0x081, {np::kCommandSetGain, 3}), 0);

  ASSERT_TRUE(answer.has_value());
  EXPECT_EQ(StatusFlags(*answer), np::kFlagConfigPending);
  EXPECT_EQ(answer->data[3], 7);  // still the gain the data is in
  EXPECT_TRUE(node.config_pending());
  EXPECT_EQ(node.chip_setting().gain_sel, 3);

  node.OnConfigApplied();
  const NodeFrame status = node.TakeStatus(0);

  EXPECT_FALSE(node.config_pending());
  EXPECT_EQ(StatusFlags(status), 0);
  EXPECT_EQ(status.data[3], 3);
}

TEST(SensorNodeTest, SetResolutionChangesTheSaturationRails) {
  SensorNode<> node(1, 0);
  node.OnBusFrame(Command(0x081, {np::kCommandSetResolution, 2}), 0);
  node.OnConfigApplied();

  // RES 2: zero field at 32768, rails at +-22000 counts.
  const NodeFrame inside = node.TakeSample(0, Conversion(32768, 32768 + 21999, 32768 - 21999));
  const NodeFrame rail = node.TakeSample(20 * kMs, Conversion(32768, 32768 + 22000, 32768));

  EXPECT_EQ(SampleStatus(inside), 0);
  EXPECT_EQ(SampleStatus(rail), np::kSampleSaturated);
}

TEST(SensorNodeTest, InvalidCommandsAreRejectedCountedAndChangeNothing) {
  SensorNode<> node(1, 0);
  const std::vector<NodeFrame> bad = {
      Command(0x081, {np::kCommandSetGain}),     // too short
      Command(0x081, {np::kCommandSetGain, 8}),  // gain out of range
      Command(0x081, {np::kCommandSetResolution, 4}),
      Command(0x081, {np::kCommandSetRate, 50}),     // rate needs two bytes
      Command(0x081, {np::kCommandSetRate, 33, 0}),  // 33 Hz is not a supported rate
      Command(0x081, {77, 0}),                       // unknown command
  };

  std::optional<NodeFrame> last_answer;
  for (const NodeFrame& frame : bad) last_answer = node.OnBusFrame(frame, 0);

  ASSERT_TRUE(last_answer.has_value());
  EXPECT_EQ(StatusFlags(*last_answer), np::kFlagCommandRejected);
  EXPECT_EQ(last_answer->data[6], bad.size());
  EXPECT_EQ(node.rx_error_count(), bad.size());
  EXPECT_EQ(node.rate_hz(), 50);
  EXPECT_FALSE(node.config_pending());
}

TEST(SensorNodeTest, CommandsForOtherNodesAreIgnoredAndBroadcastIsObeyed) {
  SensorNode<> node(2, 0);

  const std::optional<NodeFrame> other = node.OnBusFrame(Command(0x083, {np::kCommandZero, 0}), 0);
  const std::optional<NodeFrame> sample_of_other = node.OnBusFrame(Command(0x101, {1, 2}), 0);
  const std::optional<NodeFrame> broadcast =
      node.OnBusFrame(Command(0x080, {np::kCommandSetRate, 10, 0}), 0);

  EXPECT_FALSE(other.has_value());
  EXPECT_FALSE(sample_of_other.has_value());
  ASSERT_TRUE(broadcast.has_value());
  EXPECT_EQ(broadcast->id, 0x182);
  EXPECT_EQ(node.rate_hz(), 10);
}

TEST(SensorNodeTest, ZeroCommandMarksExactlyTheNextSample) {
  SensorNode<> node(3, 0);

  const std::optional<NodeFrame> answer = node.OnBusFrame(Command(0x083, {np::kCommandZero, 0}), 0);
  const NodeFrame first = node.TakeSample(0, Conversion(1, 1, 1));
  const NodeFrame second = node.TakeSample(20 * kMs, Conversion(1, 1, 1));

  ASSERT_TRUE(answer.has_value());
  EXPECT_EQ(StatusFlags(*answer), np::kFlagTarePending);
  EXPECT_EQ(SampleStatus(first), np::kSampleTare);
  EXPECT_EQ(SampleStatus(second), 0);
}

TEST(SensorNodeTest, ResetRestoresDefaultsAndRestartsTheSequence) {
  SensorNode<> node(3, 0);
  node.OnBusFrame(Command(0x083, {np::kCommandSetRate, 0xE8, 0x03}), 0);
  node.OnBusFrame(Command(0x083, {np::kCommandSetGain, 1}), 0);
  node.OnBusFrame(Command(0x083, {99, 0}), 0);
  for (int i = 0; i < 5; ++i) node.TakeSample(i * kMs, Conversion(0, 0, 0));

  const std::optional<NodeFrame> answer =
      node.OnBusFrame(Command(0x083, {np::kCommandReset, 0}), 7 * kMs);
  const NodeFrame first = node.TakeSample(7 * kMs, Conversion(0, 0, 0));

  ASSERT_TRUE(answer.has_value());
  EXPECT_EQ(StatusFlags(*answer), 0);
  EXPECT_EQ(answer->data[6], 0);  // rx errors cleared
  EXPECT_EQ(node.rate_hz(), 50);
  EXPECT_EQ(node.chip_setting().gain_sel, 7);
  EXPECT_EQ(Sequence(first), 0);
}

// ---- daisy-chain forwarding
// ----------------------------------------------------------------------

TEST(SensorNodeTest, ForwardingKeepsOrderAndCountsOverflowDrops) {
  SensorNode<4> node(1, 0);

  int queued = 0;
  for (std::uint8_t i = 0; i < 10; ++i) {
    if (node.OnDownstreamFrame(Command(0x102, {i}))) ++queued;
  }
  std::vector<std::uint8_t> forwarded;
  while (const std::optional<NodeFrame> frame = node.PopForward()) {
    forwarded.push_back(frame->data[0]);
  }

  EXPECT_EQ(queued, 4);
  EXPECT_EQ(node.forward_drops(), 6u);
  EXPECT_EQ(forwarded, (std::vector<std::uint8_t>{0, 1, 2, 3}));
}

TEST(SensorNodeTest, ForwardOverflowIsFlaggedInTheNextStatusOnly) {
  SensorNode<1> node(1, 0);
  node.OnDownstreamFrame(Command(0x102, {0}));
  node.OnDownstreamFrame(Command(0x102, {1}));

  const NodeFrame flagged = node.TakeStatus(0);
  const NodeFrame next = node.TakeStatus(kSecond);

  EXPECT_EQ(StatusFlags(flagged), np::kFlagForwardOverflow);
  EXPECT_EQ(StatusFlags(next), 0);
  EXPECT_EQ(node.forward_drops(), 1u);
}

TEST(FrameQueueTest, WrapsAroundItsStorage) {
  FrameQueue<3> queue;

  for (std::uint8_t i = 0; i < 20; ++i) {
    ASSERT_TRUE(queue.Push(Command(i, {i})));
    ASSERT_EQ(queue.Pop()->id, i);
  }

  EXPECT_EQ(queue.size(), 0u);
  EXPECT_EQ(queue.drops(), 0u);
}

// ---- UART bridge ------------------------------------------------------------------------------

NodeFrame RandomFrame(std::mt19937& rng) {
  NodeFrame frame;
  frame.id = std::uint16_t(rng() % 0x800);
  frame.len = std::uint8_t(rng() % 9);
  for (std::size_t i = 0; i < frame.len; ++i) frame.data[i] = std::uint8_t(rng());
  return frame;
}

std::vector<std::uint8_t> UartBytes(const NodeFrame& frame) {
  std::array<std::uint8_t, kUartMaxFrameBytes> buffer{};
  const std::size_t size = EncodeUartFrame(frame, buffer);
  return {buffer.begin(), buffer.begin() + std::ptrdiff_t(size)};
}

std::vector<NodeFrame> FeedAll(UartDecoder& decoder, const std::vector<std::uint8_t>& bytes) {
  std::vector<NodeFrame> frames;
  for (std::uint8_t byte : bytes) {
    if (std::optional<NodeFrame> frame = decoder.Feed(byte)) frames.push_back(*frame);
  }
  return frames;
}

TEST(UartBridgeTest, Crc8AtmMatchesTheCatalogueCheckValue) {
  const std::uint8_t text[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};

  // Poly 0x07, init 0, no reflection, no final xor: CRC-8/SMBUS in the reveng catalogue, whose
  // check value this is. (ITU I.432.1 HEC adds a final xor with 0x55; the bridge does not.)
  EXPECT_EQ(Crc8Atm(text, sizeof(text)), 0xF4);
}

TEST(UartBridgeTest, FrameLayout) {
  NodeFrame frame = Command(0x103, {0x11, 0x22});

  const std::vector<std::uint8_t> bytes = UartBytes(frame);

  const std::uint8_t covered[] = {0x03, 0x01, 0x02, 0x11, 0x22};
  EXPECT_EQ(bytes, (std::vector<std::uint8_t>{0xAA, 0x55, 0x03, 0x01, 0x02, 0x11, 0x22,
                                              Crc8Atm(covered, sizeof(covered))}));
}

TEST(UartBridgeTest, EncoderRefusesFramesNoClassicBusCarries) {
  std::array<std::uint8_t, kUartMaxFrameBytes> buffer{};
  NodeFrame long_frame = Command(0x100, {});
  long_frame.len = 9;

  EXPECT_EQ(EncodeUartFrame(long_frame, buffer), 0u);
  EXPECT_EQ(EncodeUartFrame(Command(0x800, {}), buffer), 0u);
}

TEST(UartBridgeTest, RandomFramesRoundTrip) {
  std::mt19937 rng(1);
  std::vector<NodeFrame> sent;
  std::vector<std::uint8_t> stream;
  for (int i = 0; i < 5000; ++i) {
    sent.push_back(RandomFrame(rng));
    const std::vector<std::uint8_t> bytes = UartBytes(sent.back());
    stream.insert(stream.end(), bytes.begin(), bytes.end());
  }
  UartDecoder decoder;

  const std::vector<NodeFrame> received = FeedAll(decoder, stream);

  EXPECT_EQ(received, sent);
  EXPECT_EQ(decoder.counters().bad_checksums, 0u);
  EXPECT_EQ(decoder.counters().skipped_bytes, 0u);
}

TEST(UartBridgeTest, ResyncsAfterRandomGarbage) {
  // Setup: every real frame is preceded by 0..40 random bytes, biased towards the sync bytes so
  // that garbage often looks like the start of a frame.
  std::mt19937 rng(2);
  std::vector<NodeFrame> sent;
  std::vector<std::uint8_t> stream;
  for (int i = 0; i < 3000; ++i) {
    const int garbage = int(rng() % 41);
    for (int g = 0; g < garbage; ++g) {
      const unsigned pick = rng() % 4;
      stream.push_back(pick == 0 ? 0xAA : pick == 1 ? 0x55 : std::uint8_t(rng()));
    }
    sent.push_back(RandomFrame(rng));
    const std::vector<std::uint8_t> bytes = UartBytes(sent.back());
    stream.insert(stream.end(), bytes.begin(), bytes.end());
  }
  UartDecoder decoder;

  const std::vector<NodeFrame> received = FeedAll(decoder, stream);

  // Check: every real frame arrives, in order; anything extra passed the CRC by chance.
  std::size_t next = 0;
  for (const NodeFrame& frame : received) {
    if (next < sent.size() && frame == sent[next]) ++next;
  }
  EXPECT_EQ(next, sent.size());
  const UartDecoderCounters& c = decoder.counters();
  const double candidates = double(c.frames + c.bad_checksums);
  const double false_frames = double(received.size() - sent.size());
  EXPECT_LE(false_frames, candidates / 256.0 + 5.0 * std::sqrt(candidates / 256.0) + 1.0);
  EXPECT_GT(c.bad_checksums + c.bad_lengths + c.bad_ids, 0u);
  EXPECT_GT(c.skipped_bytes, 0u);
}

TEST(UartBridgeTest, EverySingleBitFlipInIdDataOrCrcIsCaughtAndTheNextFrameSurvives) {
  // Setup: alternate clean frames with copies that have one bit flipped anywhere except the sync
  // and length bytes. CRC-8/ATM detects every single-bit error in these lengths.
  std::mt19937 rng(3);
  std::vector<NodeFrame> clean;
  std::vector<std::uint8_t> stream;
  int corrupted = 0;
  for (int i = 0; i < 4000; ++i) {
    std::vector<std::uint8_t> bad = UartBytes(RandomFrame(rng));
    std::size_t index = 0;
    do {
      index = 2 + rng() % (bad.size() - 2);
    } while (index == 4);
    bad[index] ^= std::uint8_t(1u << (rng() % 8));
    ++corrupted;
    stream.insert(stream.end(), bad.begin(), bad.end());
    clean.push_back(RandomFrame(rng));
    const std::vector<std::uint8_t> good = UartBytes(clean.back());
    stream.insert(stream.end(), good.begin(), good.end());
  }
  UartDecoder decoder;

  const std::vector<NodeFrame> received = FeedAll(decoder, stream);

  EXPECT_EQ(received, clean);
  const UartDecoderCounters& c = decoder.counters();
  EXPECT_GE(c.bad_checksums + c.bad_ids, std::uint32_t(corrupted));
}

TEST(UartBridgeTest, UniformRandomBytesYieldNoMoreFalseFramesThanTheCrcAllows) {
  std::mt19937 rng(4);
  std::vector<std::uint8_t> stream(100'000);
  for (std::uint8_t& byte : stream) byte = std::uint8_t(rng());
  UartDecoder decoder;

  const std::vector<NodeFrame> received = FeedAll(decoder, stream);

  // A candidate needs the two sync bytes, an id below 0x800 and len <= 8 (about 1 in 2.4e7 byte
  // positions), then a 1-in-256 CRC match.
  const UartDecoderCounters& c = decoder.counters();
  const double expected = double(c.frames + c.bad_checksums) / 256.0;
  EXPECT_LE(double(received.size()), expected + 5.0 * std::sqrt(expected) + 1.0);
  EXPECT_EQ(c.frames, received.size());
  EXPECT_GT(c.skipped_bytes, 99'000u);
}

TEST(UartBridgeTest, HeaderValidCandidatesPassTheCrcAtItsExpectedRate) {
  // Setup: 20000 well-formed headers with random data and a random CRC byte: each should pass with
  // probability 1/256.
  std::mt19937 rng(5);
  std::vector<std::uint8_t> stream;
  for (int i = 0; i < 20000; ++i) {
    std::vector<std::uint8_t> bytes = UartBytes(RandomFrame(rng));
    bytes.back() = std::uint8_t(rng());
    stream.insert(stream.end(), bytes.begin(), bytes.end());
  }
  UartDecoder decoder;

  FeedAll(decoder, stream);

  const UartDecoderCounters& c = decoder.counters();
  const double candidates = double(c.frames + c.bad_checksums);
  const double expected = candidates / 256.0;
  EXPECT_GE(candidates, 20000.0);
  EXPECT_NEAR(double(c.frames), expected, 5.0 * std::sqrt(expected));
}

TEST(UartBridgeTest, CountsBadLengthAndBadId) {
  UartDecoder decoder;

  FeedAll(decoder, {0xAA, 0x55, 0x00, 0x01, 9});  // len 9
  FeedAll(decoder, {0xAA, 0x55, 0x00, 0x08, 0});  // id 0x800
  const std::vector<NodeFrame> after = FeedAll(decoder, UartBytes(Command(0x105, {7})));

  EXPECT_EQ(decoder.counters().bad_lengths, 1u);
  EXPECT_EQ(decoder.counters().bad_ids, 1u);
  EXPECT_EQ(after, (std::vector<NodeFrame>{Command(0x105, {7})}));
}

TEST(NodeSampleTest, UnpacksWhatPackSampleFramePackedAndOnlySampleFrames) {
  for (std::uint8_t node = np::kFirstNodeId; node <= np::kLastNodeId; ++node) {
    const NodeFrame frame = PackSampleFrame(node, {0x1234, 0xFFFF, 7}, 200, np::kSampleSaturated);
    const std::optional<NodeSample> sample = UnpackSampleFrame(frame);
    ASSERT_TRUE(sample.has_value()) << int(node);
    EXPECT_EQ(*sample, (NodeSample{node, {0x1234, 0xFFFF, 7}, 200, np::kSampleSaturated}));
  }
  NodeFrame short_sample = PackSampleFrame(3, {1, 2, 3}, 0, 0);
  short_sample.len = 7;
  EXPECT_FALSE(UnpackSampleFrame(short_sample));
  NodeFrame node_zero = PackSampleFrame(1, {1, 2, 3}, 0, 0);
  node_zero.id = np::kSampleBaseId;
  EXPECT_FALSE(UnpackSampleFrame(node_zero));
  NodeFrame node_eight = node_zero;
  node_eight.id = np::kSampleBaseId + 8;
  EXPECT_FALSE(UnpackSampleFrame(node_eight));
  SensorNode<> node(2, 0);
  EXPECT_FALSE(UnpackSampleFrame(node.TakeStatus(0)));
}

}  // namespace
}  // namespace hilrig::dut_fw
