#include "rig/gs_usb_protocol.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "tests/rig/fake_gs_usb_device.h"

namespace hilrig::rig {
namespace {

using Bytes = std::vector<std::uint8_t>;

template <std::size_t N>
Bytes ToBytes(const std::array<std::uint8_t, N>& array) {
  return Bytes(array.begin(), array.end());
}

TEST(GsUsbProtocolTest, HostFormatIsBeefLittleEndian) {
  EXPECT_EQ(ToBytes(EncodeGsUsbHostFormat()), (Bytes{0xEF, 0xBE, 0x00, 0x00}));
}

TEST(GsUsbProtocolTest, DeviceConfigLayoutMatchesTheDriverStruct) {
  // reserved1..3, icount, sw_version, hw_version
  const Bytes wire = {0, 0, 0, 1, 0x02, 0, 0, 0, 0x34, 0x12, 0, 0};

  const Result<GsUsbDeviceConfig> config = DecodeGsUsbDeviceConfig(wire);

  ASSERT_TRUE(config.ok()) << config.error().message;
  EXPECT_EQ(config.value(),
            (GsUsbDeviceConfig{.icount = 1, .sw_version = 2, .hw_version = 0x1234}));
  EXPECT_EQ(config.value().channel_count(), 2u);
  EXPECT_EQ(ToBytes(EncodeGsUsbDeviceConfig(config.value())), wire);
}

TEST(GsUsbProtocolTest, ShortDeviceConfigIsAnError) {
  EXPECT_FALSE(DecodeGsUsbDeviceConfig(Bytes(11, 0)).ok());
}

TEST(GsUsbProtocolTest, BtConstLayoutIsTenLittleEndianWords) {
  const GsUsbBtConst bt_const = CandleLightBtConst();

  const Bytes wire = ToBytes(EncodeGsUsbBtConst(bt_const));

  ASSERT_EQ(wire.size(), 40u);
  EXPECT_EQ(Bytes(wire.begin() + 4, wire.begin() + 8), (Bytes{0x00, 0x6C, 0xDC, 0x02}));  // 48 MHz
  EXPECT_EQ(wire[12], 16);                                                            // tseg1_max
  EXPECT_EQ(wire[20], 8);                                                             // tseg2_max
  EXPECT_EQ(wire[24], 4);                                                             // sjw_max
  EXPECT_EQ(Bytes(wire.begin() + 32, wire.begin() + 36), (Bytes{0x00, 0x04, 0, 0}));  // brp_max
  const Result<GsUsbBtConst> decoded = DecodeGsUsbBtConst(wire);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded.value(), bt_const);
}

TEST(GsUsbProtocolTest, BtConstExtRoundTripsWithDataLimits) {
  const GsUsbBtConst bt_const = FdCanBtConst();

  const Bytes wire = ToBytes(EncodeGsUsbBtConstExt(bt_const));
  const Result<GsUsbBtConst> decoded = DecodeGsUsbBtConstExt(wire);

  ASSERT_EQ(wire.size(), 72u);
  EXPECT_EQ(wire[44], 32);  // dtseg1_max follows the ten BT_CONST words and dtseg1_min
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded.value(), bt_const);
}

TEST(GsUsbProtocolTest, BitTimingAndModeLayouts) {
  const GsUsbBitTiming timing{.prop_seg = 6, .phase_seg1 = 7, .phase_seg2 = 2, .sjw = 1, .brp = 3};

  const Bytes timing_wire = ToBytes(EncodeGsUsbBitTiming(timing));
  const Bytes mode_wire = ToBytes(
      EncodeGsUsbMode({kGsUsbModeStart, gs_usb_feature::kHwTimestamp | gs_usb_feature::kFd}));

  EXPECT_EQ(timing_wire, (Bytes{6, 0, 0, 0, 7, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0, 3, 0, 0, 0}));
  EXPECT_EQ(DecodeGsUsbBitTiming(timing_wire).value(), timing);
  EXPECT_EQ(mode_wire, (Bytes{1, 0, 0, 0, 0x10, 0x01, 0, 0}));
}

TEST(GsUsbProtocolTest, ClassicHostFrameLayout) {
  GsUsbHostFrame host_frame;
  host_frame.echo_id = 3;
  host_frame.frame = CanFrame::ClassicExtended(0x12345678, std::array<std::uint8_t, 3>{1, 2, 3});
  host_frame.channel = 1;

  const Bytes wire = EncodeGsUsbHostFrame(host_frame);

  EXPECT_EQ(wire, (Bytes{3, 0, 0, 0, 0x78, 0x56, 0x34, 0x92, 3, 1, 0, 0,  // header, EFF set
                         1, 2, 3, 0, 0,    0,    0,    0}));
}

TEST(GsUsbProtocolTest, RxFrameWithTimestampDecodes) {
  const Bytes wire = {0xFF, 0xFF, 0xFF, 0xFF, 0x23, 0x01, 0, 0, 2,    0,    0,    0,
                      0xAA, 0xBB, 0,    0,    0,    0,    0, 0, 0x78, 0x56, 0x34, 0x12};

  const Result<GsUsbHostFrame> decoded = DecodeGsUsbHostFrame(wire, /*timestamps_on=*/true);

  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_FALSE(decoded.value().is_tx_echo());
  EXPECT_EQ(decoded.value().frame,
            CanFrame::Classic(0x123, std::array<std::uint8_t, 2>{0xAA, 0xBB}));
  EXPECT_EQ(decoded.value().timestamp_us, 0x12345678u);
}

TEST(GsUsbProtocolTest, EveryKindOfFrameRoundTrips) {
  const std::vector<CanFrame> frames = {
      CanFrame::Classic(0x7FF, std::array<std::uint8_t, 8>{1, 2, 3, 4, 5, 6, 7, 8}),
      CanFrame::Remote(0x456, 4, /*extended=*/false),
      CanFrame::Remote(0x1ABCDEF0, 8, /*extended=*/true),
      CanFrame::Fd(0x100, std::vector<std::uint8_t>(64, 0xEE), /*bitrate_switch=*/true),
      CanFrame::FdExtended(0x1000, std::vector<std::uint8_t>(12, 0x11), false),
      CanFrame::ErrorFrame(can_error::kController | can_error::kCounters,
                           {0, can_error::kCtrlRxPassive, 0, 0, 0, 0, 100, 130}),
  };
  for (const CanFrame& frame : frames) {
    for (const bool with_timestamp : {false, true}) {
      GsUsbHostFrame host_frame;
      host_frame.echo_id = 7;
      host_frame.frame = frame;
      if (with_timestamp) host_frame.timestamp_us = 0xFFFFFFF0;

      const Bytes wire = EncodeGsUsbHostFrame(host_frame);
      const Result<GsUsbHostFrame> decoded = DecodeGsUsbHostFrame(wire, with_timestamp);

      EXPECT_EQ(wire.size(), GsUsbHostFrameBytes(frame.fd, with_timestamp)) << frame;
      ASSERT_TRUE(decoded.ok()) << frame << ": " << decoded.error().message;
      EXPECT_EQ(decoded.value(), host_frame) << frame;
    }
  }
}

TEST(GsUsbProtocolTest, FdFlagsSitInTheFlagsByte) {
  GsUsbHostFrame host_frame;
  host_frame.frame = CanFrame::Fd(0x10, std::vector<std::uint8_t>(20, 1), /*bitrate_switch=*/true);

  const Bytes wire = EncodeGsUsbHostFrame(host_frame);

  EXPECT_EQ(wire[8], 11);  // DLC of 20 bytes
  EXPECT_EQ(wire[10], gs_usb_frame_flag::kFd | gs_usb_frame_flag::kBitrateSwitch);
  EXPECT_EQ(wire.size(), 76u);
}

TEST(GsUsbProtocolTest, ShortOrInvalidHostFramesAreErrors) {
  Bytes wire = EncodeGsUsbHostFrame(GsUsbHostFrame{.echo_id = 1,
                                                   .frame = CanFrame::Classic(0x1, {}),
                                                   .channel = 0,
                                                   .overflow = false,
                                                   .timestamp_us = std::nullopt});

  EXPECT_FALSE(DecodeGsUsbHostFrame(Bytes(wire.begin(), wire.begin() + 11), false).ok());
  EXPECT_FALSE(DecodeGsUsbHostFrame(wire, /*timestamps_on=*/true).ok());  // no room for it
  wire[10] = gs_usb_frame_flag::kFd;  // says FD but carries 8 data bytes
  EXPECT_FALSE(DecodeGsUsbHostFrame(wire, false).ok());
}

TEST(GsUsbProtocolTest, OverflowFlagIsReported) {
  Bytes wire = EncodeGsUsbHostFrame(GsUsbHostFrame{.echo_id = 1,
                                                   .frame = CanFrame::Classic(0x1, {}),
                                                   .channel = 0,
                                                   .overflow = false,
                                                   .timestamp_us = std::nullopt});
  wire[10] = gs_usb_frame_flag::kOverflow;

  EXPECT_TRUE(DecodeGsUsbHostFrame(wire, false).value().overflow);
}

struct TimingCase {
  std::uint32_t fclk_hz;
  std::int64_t bitrate_bps;
  GsUsbTimingLimits limits;
};

TEST(GsUsbProtocolTest, BitTimingHitsBitrateAndSamplePoint) {
  const GsUsbTimingLimits bxcan = CandleLightBtConst().nominal;
  const GsUsbTimingLimits fdcan = FdCanBtConst().nominal;
  const std::vector<TimingCase> cases = {{48'000'000, 1'000'000, bxcan},
                                         {48'000'000, 500'000, bxcan},
                                         {170'000'000, 1'000'000, fdcan},
                                         {170'000'000, 500'000, fdcan},
                                         {170'000'000, 1'000'000, bxcan}};
  for (const TimingCase& c : cases) {
    const Result<GsUsbBitTiming> timing =
        CalculateGsUsbBitTiming(c.bitrate_bps, c.fclk_hz, c.limits);

    ASSERT_TRUE(timing.ok()) << c.fclk_hz << " " << c.bitrate_bps << timing.error().message;
    const GsUsbBitTiming& t = timing.value();
    EXPECT_NEAR(t.bitrate_bps(c.fclk_hz), c.bitrate_bps, c.bitrate_bps * 0.005);
    EXPECT_NEAR(t.sample_point(), 0.875, 0.02) << c.fclk_hz << " " << c.bitrate_bps;
    EXPECT_GE(t.prop_seg + t.phase_seg1, c.limits.tseg1_min);
    EXPECT_LE(t.prop_seg + t.phase_seg1, c.limits.tseg1_max);
    EXPECT_GE(t.phase_seg2, c.limits.tseg2_min);
    EXPECT_LE(t.phase_seg2, c.limits.tseg2_max);
    EXPECT_GE(t.sjw, 1u);
    EXPECT_LE(t.sjw, std::min(c.limits.sjw_max, t.phase_seg2));
  }
}

TEST(GsUsbProtocolTest, CandleLightOneMegabitIsTheTextbookTiming) {
  const Result<GsUsbBitTiming> timing =
      CalculateGsUsbBitTiming(1'000'000, 48'000'000, CandleLightBtConst().nominal);

  ASSERT_TRUE(timing.ok());
  // 48 MHz / 3 = 16 quanta per bit, 14 before the sample point: exactly 87.5 %.
  EXPECT_EQ(timing.value(),
            (GsUsbBitTiming{.prop_seg = 6, .phase_seg1 = 7, .phase_seg2 = 2, .sjw = 1, .brp = 3}));
}

TEST(GsUsbProtocolTest, UnreachableBitrateIsAnError) {
  // 48 MHz cannot make 10 Mbit/s: 5 quanta give 9.6 Mbit/s, 4 % off.
  const Result<GsUsbBitTiming> timing =
      CalculateGsUsbBitTiming(10'000'000, 48'000'000, CandleLightBtConst().nominal);

  ASSERT_FALSE(timing.ok());
  EXPECT_NE(timing.error().message.find("0.5 %"), std::string::npos) << timing.error().message;
}

TEST(GsUsbProtocolTest, TimestampUnwrapCrossesThe32BitWrap) {
  GsUsbTimestampUnwrapper state;
  const std::vector<std::uint32_t> device_us = {0xFFFFFF00, 0xFFFFFFFF, 0x00000010, 0x00001000};
  std::vector<std::int64_t> times_ns;

  for (const std::uint32_t ts : device_us) {
    const GsUsbUnwrappedTime unwrapped = UnwrapGsUsbTimestamp(state, ts);
    state = unwrapped.state;
    times_ns.push_back(unwrapped.time_ns);
  }

  const std::int64_t first_ns = std::int64_t{0xFFFFFF00} * 1000;
  EXPECT_EQ(times_ns, (std::vector<std::int64_t>{first_ns, first_ns + 255'000, first_ns + 272'000,
                                                 first_ns + (0x1000 + 0x100) * 1000}));
}

TEST(GsUsbProtocolTest, TimestampUnwrapToleratesSmallReordering) {
  GsUsbTimestampUnwrapper state = UnwrapGsUsbTimestamp({}, 5).state;

  const GsUsbUnwrappedTime earlier = UnwrapGsUsbTimestamp(state, 0xFFFFFFFE);  // 7 µs before

  EXPECT_EQ(earlier.time_ns, -2'000);
}

}  // namespace
}  // namespace hilrig::rig
