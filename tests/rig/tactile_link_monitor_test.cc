#include "rig/tactile_link_monitor.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <sstream>
#include <vector>

namespace hilrig::rig {
namespace {

CanFrame SampleFrame(std::uint8_t node_id, std::uint8_t sequence, std::uint8_t status = 0) {
  return EncodeTactileSample(
      {.node_id = node_id, .code = {1, 2, 3}, .sequence = sequence, .status = status});
}

TEST(TactileLinkMonitorTest, CountsCleanStreamWithoutComplaints) {
  TactileLinkMonitor monitor;

  for (int i = 0; i < 600; ++i) {
    for (std::uint8_t node = 1; node <= 7; ++node) {
      ASSERT_TRUE(monitor.Observe(SampleFrame(node, static_cast<std::uint8_t>(i))).ok());
    }
  }

  for (std::uint8_t node = 1; node <= 7; ++node) {
    TactileNodeCounters expected;
    expected.frames = 600;
    expected.samples = 600;
    EXPECT_EQ(monitor.node(node), expected) << "node " << int(node);
  }
  EXPECT_EQ(monitor.bus().frames, 4200u);
}

TEST(TactileLinkMonitorTest, SequenceWrapIsNotAGap) {
  TactileLinkMonitor monitor;

  ASSERT_TRUE(monitor.Observe(SampleFrame(1, 254)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(1, 255)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(1, 0)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(1, 1)).ok());

  EXPECT_EQ(monitor.node(1).sequence_gaps, 0u);
  EXPECT_EQ(monitor.node(1).duplicates, 0u);
}

TEST(TactileLinkMonitorTest, GapAcrossTheWrapCountsTheLostSamples) {
  TactileLinkMonitor monitor;

  ASSERT_TRUE(monitor.Observe(SampleFrame(2, 253)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(2, 2)).ok());  // 254, 255, 0, 1 lost

  EXPECT_EQ(monitor.node(2).sequence_gaps, 1u);
  EXPECT_EQ(monitor.node(2).lost_samples, 4u);
}

TEST(TactileLinkMonitorTest, RepeatedSequenceIsADuplicateNotAGap) {
  TactileLinkMonitor monitor;

  ASSERT_TRUE(monitor.Observe(SampleFrame(3, 10)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(3, 10)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(3, 11)).ok());

  EXPECT_EQ(monitor.node(3).duplicates, 1u);
  EXPECT_EQ(monitor.node(3).sequence_gaps, 0u);
}

TEST(TactileLinkMonitorTest, SequencesAreTrackedPerNode) {
  TactileLinkMonitor monitor;

  ASSERT_TRUE(monitor.Observe(SampleFrame(1, 0)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(2, 100)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(1, 1)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(2, 101)).ok());

  EXPECT_EQ(monitor.Totals().sequence_gaps, 0u);
}

TEST(TactileLinkMonitorTest, ResetCommandRestartsSequenceTracking) {
  TactileLinkMonitor monitor;
  ASSERT_TRUE(monitor.Observe(SampleFrame(5, 77)).ok());

  ASSERT_TRUE(
      monitor.Observe(EncodeTactileConfig({.node_id = 0, .command = TactileCommand::kReset})).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(5, 0)).ok());

  EXPECT_EQ(monitor.node(5).sequence_gaps, 0u);
  EXPECT_EQ(monitor.node(0).commands, 1u);
}

TEST(TactileLinkMonitorTest, CountsStatusFlagsOfSamples) {
  TactileLinkMonitor monitor;

  ASSERT_TRUE(monitor.Observe(SampleFrame(6, 0, tactile_bus::kSampleStale)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(6, 1, tactile_bus::kSampleSaturated)).ok());
  ASSERT_TRUE(monitor
                  .Observe(SampleFrame(
                      6, 2, tactile_bus::kSampleConversionError | tactile_bus::kSampleStale))
                  .ok());

  EXPECT_EQ(monitor.node(6).stale, 2u);
  EXPECT_EQ(monitor.node(6).saturated, 1u);
  EXPECT_EQ(monitor.node(6).conversion_errors, 1u);
}

TEST(TactileLinkMonitorTest, WrongDlcIsCountedAgainstItsNodeAndReturnedAsError) {
  TactileLinkMonitor monitor;
  const std::vector<std::uint8_t> seven(7, 0);

  const Result<TactileMessage> result = monitor.Observe(CanFrame::Classic(0x104, seven));

  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("expected 8 bytes, got 7"), std::string::npos);
  EXPECT_EQ(monitor.node(4).wrong_dlc, 1u);
  EXPECT_EQ(monitor.node(4).frames, 1u);
  EXPECT_EQ(monitor.node(4).samples, 0u);
}

TEST(TactileLinkMonitorTest, BadCommandIsCountedSeparatelyFromWrongDlc) {
  TactileLinkMonitor monitor;
  const std::vector<std::uint8_t> unknown_command = {42, 0};
  const std::vector<std::uint8_t> too_short = {4};

  EXPECT_FALSE(monitor.Observe(CanFrame::Classic(0x081, unknown_command)).ok());
  EXPECT_FALSE(monitor.Observe(CanFrame::Classic(0x081, too_short)).ok());

  EXPECT_EQ(monitor.node(1).bad_commands, 1u);
  EXPECT_EQ(monitor.node(1).wrong_dlc, 1u);
}

TEST(TactileLinkMonitorTest, UnknownIdsAndForeignFramesAreCountedBusWide) {
  TactileLinkMonitor monitor;

  EXPECT_FALSE(monitor.Observe(CanFrame::Classic(0x7FF, {})).ok());
  EXPECT_FALSE(monitor.Observe(CanFrame::ClassicExtended(0x101, {})).ok());
  EXPECT_FALSE(monitor.Observe(CanFrame::Remote(0x101, 8, false)).ok());
  EXPECT_FALSE(monitor.Observe(CanFrame::ErrorFrame(0x40, {})).ok());

  EXPECT_EQ(monitor.bus().unknown_ids, 1u);
  EXPECT_EQ(monitor.bus().not_classic_data, 3u);
  EXPECT_EQ(monitor.Totals().frames, 0u);
}

TEST(TactileLinkMonitorTest, RandomGarbageIsCountedNeverFatal) {
  // Setup: frames with random flags, ids around the tactile ranges, lengths and bytes.
  std::mt19937 rng(4);
  TactileLinkMonitor monitor;
  std::uint64_t rejected = 0;
  constexpr int kFrames = 20000;

  for (int i = 0; i < kFrames; ++i) {
    CanFrame frame;
    frame.id = rng() % 0x200;
    frame.extended = rng() % 16 == 0;
    frame.remote = rng() % 16 == 0;
    frame.fd = rng() % 16 == 0;
    frame.error = rng() % 16 == 0;
    frame.length = static_cast<std::uint8_t>(rng() % 4 == 0 ? rng() % 256 : 8);
    for (std::uint8_t& byte : frame.data) byte = static_cast<std::uint8_t>(rng());
    if (!monitor.Observe(frame).ok()) ++rejected;
  }

  // Check: every frame landed in exactly one bucket.
  const TactileNodeCounters totals = monitor.Totals();
  EXPECT_EQ(monitor.bus().frames, std::uint64_t(kFrames));
  EXPECT_EQ(totals.frames + monitor.bus().unknown_ids + monitor.bus().not_classic_data,
            std::uint64_t(kFrames));
  EXPECT_EQ(totals.wrong_dlc + totals.bad_commands + monitor.bus().unknown_ids +
                monitor.bus().not_classic_data,
            rejected);
  EXPECT_GT(totals.wrong_dlc, 0u);
  EXPECT_GT(totals.sequence_gaps, 0u);
}

TEST(TactileLinkMonitorTest, PrintsOneLinePerActiveAddress) {
  TactileLinkMonitor monitor;
  ASSERT_TRUE(monitor.Observe(SampleFrame(1, 0)).ok());
  ASSERT_TRUE(monitor.Observe(SampleFrame(1, 5)).ok());

  std::ostringstream text;
  text << monitor;

  EXPECT_EQ(text.str(),
            "node 1: frames 2, samples 2, statuses 0, commands 0, wrong dlc 0, bad commands 0, "
            "gaps 1 (4 lost), duplicates 0, stale 0, saturated 0, conversion errors 0\n"
            "bus: frames 2, unknown ids 0, not classic data 0\n");
}

}  // namespace
}  // namespace hilrig::rig
