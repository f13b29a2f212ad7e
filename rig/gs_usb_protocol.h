// The gs_usb wire protocol (candleLight, CANable, and the other adapters Linux's gs_usb driver
// serves), kept apart from any USB transport so that it is pure functions on byte spans, testable
// without a device and shared by the real bus and the fake device in the tests.
//
// A gs_usb adapter is configured by vendor control requests on interface 0 (host byte order,
// device config, bit-timing constants, bit timing, mode start/stop) and exchanges CAN frames as
// "host frames" on a bulk IN and a bulk OUT endpoint. Every multi-byte field is little-endian
// (the host format request announces 0x0000beef so old firmware does not byte-swap). Layouts, as
// in the Linux driver's packed structs (byte offsets):
//
//   device config (12)  0 u8 reserved x3   3 u8 icount (channels - 1)   4 u32 sw_version
//                       8 u32 hw_version
//   bt const (40)       u32 x10: feature, fclk_can, tseg1_min, tseg1_max, tseg2_min, tseg2_max,
//                       sjw_max, brp_min, brp_max, brp_inc
//   bt const ext (72)   the 10 above, then dtseg1_min, dtseg1_max, dtseg2_min, dtseg2_max,
//                       dsjw_max, dbrp_min, dbrp_max, dbrp_inc
//   bit timing (20)     u32 x5: prop_seg, phase_seg1, phase_seg2, sjw, brp
//   mode (8)            u32 mode (0 reset, 1 start), u32 flags
//   host frame          0 u32 echo_id   4 u32 can_id (Linux canid_t: EFF/RTR/ERR flag bits)
//                       8 u8 dlc   9 u8 channel   10 u8 flags   11 u8 reserved   12 data (8, or 64
//                       for FD)   then, when hardware timestamps are on, u32 timestamp in µs
//
// A frame the device sends with echo_id 0xFFFFFFFF was received from the bus; any other echo_id
// confirms that the host frame sent with that id went out on the wire.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "rig/can_bus.h"
#include "rig/can_frame.h"
#include "rig/result.h"

namespace hilrig::rig {

// bRequest of the vendor control requests (enum gs_usb_breq).
namespace gs_usb_request {
inline constexpr std::uint8_t kHostFormat = 0;
inline constexpr std::uint8_t kBitTiming = 1;
inline constexpr std::uint8_t kMode = 2;
inline constexpr std::uint8_t kBerr = 3;
inline constexpr std::uint8_t kBtConst = 4;
inline constexpr std::uint8_t kDeviceConfig = 5;
inline constexpr std::uint8_t kTimestamp = 6;
inline constexpr std::uint8_t kIdentify = 7;
inline constexpr std::uint8_t kDataBitTiming = 10;
inline constexpr std::uint8_t kBtConstExt = 11;
}  // namespace gs_usb_request

// Feature bits (BT_CONST) and the matching mode flags (MODE start) share one numbering.
namespace gs_usb_feature {
inline constexpr std::uint32_t kListenOnly = 1U << 0;
inline constexpr std::uint32_t kLoopBack = 1U << 1;
inline constexpr std::uint32_t kTripleSample = 1U << 2;
inline constexpr std::uint32_t kOneShot = 1U << 3;
inline constexpr std::uint32_t kHwTimestamp = 1U << 4;
inline constexpr std::uint32_t kIdentify = 1U << 5;
inline constexpr std::uint32_t kUserId = 1U << 6;
inline constexpr std::uint32_t kPadPacketsToMaxSize = 1U << 7;
inline constexpr std::uint32_t kFd = 1U << 8;
inline constexpr std::uint32_t kBtConstExt = 1U << 10;
}  // namespace gs_usb_feature

// Host frame flags byte.
namespace gs_usb_frame_flag {
inline constexpr std::uint8_t kOverflow = 1U << 0;  // the device dropped RX frames before this one
inline constexpr std::uint8_t kFd = 1U << 1;
inline constexpr std::uint8_t kBitrateSwitch = 1U << 2;
inline constexpr std::uint8_t kErrorStateIndicator = 1U << 3;
}  // namespace gs_usb_frame_flag

inline constexpr std::uint32_t kGsUsbHostFormat = 0x0000beef;
inline constexpr std::uint16_t kGsUsbHostFormatValue = 1;  // wValue of the host format request
inline constexpr std::uint32_t kGsUsbEchoIdRx = 0xFFFFFFFF;
inline constexpr std::uint32_t kGsUsbModeReset = 0;
inline constexpr std::uint32_t kGsUsbModeStart = 1;

inline constexpr std::size_t kGsUsbHostConfigBytes = 4;
inline constexpr std::size_t kGsUsbDeviceConfigBytes = 12;
inline constexpr std::size_t kGsUsbBtConstBytes = 40;
inline constexpr std::size_t kGsUsbBtConstExtBytes = 72;
inline constexpr std::size_t kGsUsbBitTimingBytes = 20;
inline constexpr std::size_t kGsUsbModeBytes = 8;
inline constexpr std::size_t kGsUsbHostFrameHeaderBytes = 12;
inline constexpr std::size_t kGsUsbTimestampBytes = 4;
inline constexpr std::size_t kGsUsbMaxHostFrameBytes =
    kGsUsbHostFrameHeaderBytes + CanFrame::kMaxFdPayload + kGsUsbTimestampBytes;

std::array<std::uint8_t, kGsUsbHostConfigBytes> EncodeGsUsbHostFormat();

struct GsUsbDeviceConfig {
  std::uint8_t icount = 0;  // number of CAN channels minus one
  std::uint32_t sw_version = 0;
  std::uint32_t hw_version = 0;

  std::size_t channel_count() const { return std::size_t{icount} + 1; }
  friend bool operator==(const GsUsbDeviceConfig&, const GsUsbDeviceConfig&) = default;
};
std::array<std::uint8_t, kGsUsbDeviceConfigBytes> EncodeGsUsbDeviceConfig(
    const GsUsbDeviceConfig& config);
Result<GsUsbDeviceConfig> DecodeGsUsbDeviceConfig(std::span<const std::uint8_t> bytes);

// What a controller's bit-timing registers accept, in time quanta (tq) and prescaler steps.
struct GsUsbTimingLimits {
  std::uint32_t tseg1_min = 1;
  std::uint32_t tseg1_max = 16;
  std::uint32_t tseg2_min = 1;
  std::uint32_t tseg2_max = 8;
  std::uint32_t sjw_max = 4;
  std::uint32_t brp_min = 1;
  std::uint32_t brp_max = 1024;
  std::uint32_t brp_inc = 1;
  friend bool operator==(const GsUsbTimingLimits&, const GsUsbTimingLimits&) = default;
};

// BT_CONST, and with FD devices BT_CONST_EXT (which adds the data-phase limits).
struct GsUsbBtConst {
  std::uint32_t features = 0;  // gs_usb_feature bits
  std::uint32_t fclk_can_hz = 0;
  GsUsbTimingLimits nominal{};
  std::optional<GsUsbTimingLimits> data;  // only from BT_CONST_EXT
  friend bool operator==(const GsUsbBtConst&, const GsUsbBtConst&) = default;
};
std::array<std::uint8_t, kGsUsbBtConstBytes> EncodeGsUsbBtConst(const GsUsbBtConst& bt_const);
// `bt_const.data` must be set.
std::array<std::uint8_t, kGsUsbBtConstExtBytes> EncodeGsUsbBtConstExt(const GsUsbBtConst& bt_const);
Result<GsUsbBtConst> DecodeGsUsbBtConst(std::span<const std::uint8_t> bytes);
Result<GsUsbBtConst> DecodeGsUsbBtConstExt(std::span<const std::uint8_t> bytes);

struct GsUsbBitTiming {
  std::uint32_t prop_seg = 0;
  std::uint32_t phase_seg1 = 0;
  std::uint32_t phase_seg2 = 0;
  std::uint32_t sjw = 0;
  std::uint32_t brp = 0;

  // tseg1 = prop_seg + phase_seg1; a bit is 1 (sync) + tseg1 + tseg2 quanta.
  std::uint32_t tq_per_bit() const { return 1 + prop_seg + phase_seg1 + phase_seg2; }
  double sample_point() const;
  double bitrate_bps(std::uint32_t fclk_can_hz) const;
  friend bool operator==(const GsUsbBitTiming&, const GsUsbBitTiming&) = default;
};
std::array<std::uint8_t, kGsUsbBitTimingBytes> EncodeGsUsbBitTiming(const GsUsbBitTiming& timing);
Result<GsUsbBitTiming> DecodeGsUsbBitTiming(std::span<const std::uint8_t> bytes);

inline constexpr double kGsUsbDefaultSamplePoint = 0.875;  // CiA 301's recommendation
inline constexpr double kGsUsbMaxBitrateError = 0.005;

// The timing closest to `bitrate_bps` for a controller clocked at fclk_can_hz within `limits`:
// first the smallest bitrate error, then the sample point nearest the target, then the smallest
// prescaler (more quanta per bit, finer resynchronisation). Fails if no timing lands within
// kGsUsbMaxBitrateError of the bitrate.
Result<GsUsbBitTiming> CalculateGsUsbBitTiming(std::int64_t bitrate_bps, std::uint32_t fclk_can_hz,
                                               const GsUsbTimingLimits& limits,
                                               double sample_point = kGsUsbDefaultSamplePoint);

struct GsUsbMode {
  std::uint32_t mode = kGsUsbModeReset;
  std::uint32_t flags = 0;  // gs_usb_feature bits
  friend bool operator==(const GsUsbMode&, const GsUsbMode&) = default;
};
std::array<std::uint8_t, kGsUsbModeBytes> EncodeGsUsbMode(const GsUsbMode& mode);
Result<GsUsbMode> DecodeGsUsbMode(std::span<const std::uint8_t> bytes);

struct GsUsbHostFrame {
  std::uint32_t echo_id = kGsUsbEchoIdRx;
  CanFrame frame;
  std::uint8_t channel = 0;
  bool overflow = false;                      // flag from the device: RX frames were lost
  std::optional<std::uint32_t> timestamp_us;  // device time, only with hardware timestamps

  bool is_tx_echo() const { return echo_id != kGsUsbEchoIdRx; }
  friend bool operator==(const GsUsbHostFrame&, const GsUsbHostFrame&) = default;
};

// Bytes of a host frame: the data area is 8 bytes for classic frames and 64 for FD frames.
std::size_t GsUsbHostFrameBytes(bool fd, bool with_timestamp);
// The frame must be valid (ValidateFrame). The timestamp is written iff it is set.
std::vector<std::uint8_t> EncodeGsUsbHostFrame(const GsUsbHostFrame& host_frame);
// `timestamps_on`: the mode was started with hardware timestamps, so the field follows the data.
// Extra trailing bytes (padding to the packet size) are ignored; short packets and frames that
// ValidateFrame refuses are errors.
Result<GsUsbHostFrame> DecodeGsUsbHostFrame(std::span<const std::uint8_t> bytes,
                                            bool timestamps_on);

// Extends the device's 32-bit microsecond clock (which wraps every ~71.6 minutes) to 64-bit
// nanoseconds. Each timestamp is taken as the previous one plus the signed 32-bit difference, so
// wraps are crossed and the small reorderings between echoes and RX frames do not look like a
// wrap; consecutive timestamps must be less than 2^31 µs (~35 min) apart.
struct GsUsbTimestampUnwrapper {
  bool started = false;
  std::uint32_t last_us = 0;
  std::int64_t last_extended_us = 0;
};
struct GsUsbUnwrappedTime {
  GsUsbTimestampUnwrapper state;
  std::int64_t time_ns = 0;
};
GsUsbUnwrappedTime UnwrapGsUsbTimestamp(GsUsbTimestampUnwrapper state, std::uint32_t timestamp_us);

}  // namespace hilrig::rig
