#include "rig/gs_usb_protocol.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace hilrig::rig {

namespace {

void PutU32(std::span<std::uint8_t> out, std::size_t offset, std::uint32_t value) {
  for (std::size_t i = 0; i < 4; ++i) out[offset + i] = static_cast<std::uint8_t>(value >> (8 * i));
}

std::uint32_t GetU32(std::span<const std::uint8_t> in, std::size_t offset) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < 4; ++i) value |= std::uint32_t{in[offset + i]} << (8 * i);
  return value;
}

Result<void> ExpectSize(std::span<const std::uint8_t> bytes, std::size_t size, const char* what) {
  if (bytes.size() != size) {
    return MakeError(std::string("gs_usb ") + what + ": expected " + std::to_string(size) +
                     " bytes, got " + std::to_string(bytes.size()));
  }
  return {};
}

// The limits fill eight consecutive u32 fields in BT_CONST and BT_CONST_EXT alike.
void PutLimits(std::span<std::uint8_t> out, std::size_t offset, const GsUsbTimingLimits& limits) {
  const std::array<std::uint32_t, 8> fields = {limits.tseg1_min, limits.tseg1_max, limits.tseg2_min,
                                               limits.tseg2_max, limits.sjw_max,   limits.brp_min,
                                               limits.brp_max,   limits.brp_inc};
  for (std::size_t i = 0; i < fields.size(); ++i) PutU32(out, offset + 4 * i, fields[i]);
}

GsUsbTimingLimits GetLimits(std::span<const std::uint8_t> in, std::size_t offset) {
  GsUsbTimingLimits limits;
  limits.tseg1_min = GetU32(in, offset + 0);
  limits.tseg1_max = GetU32(in, offset + 4);
  limits.tseg2_min = GetU32(in, offset + 8);
  limits.tseg2_max = GetU32(in, offset + 12);
  limits.sjw_max = GetU32(in, offset + 16);
  limits.brp_min = GetU32(in, offset + 20);
  limits.brp_max = GetU32(in, offset + 24);
  limits.brp_inc = GetU32(in, offset + 28);
  return limits;
}

// Splits tseg1 for a given quanta count so the sample point lands nearest the target; nullopt if
// the limits leave no split for this many quanta.
struct SegmentSplit {
  std::uint32_t tseg1 = 0;
  std::uint32_t tseg2 = 0;
};
std::optional<SegmentSplit> SplitSegments(std::uint32_t tq_per_bit, const GsUsbTimingLimits& limits,
                                          double sample_point) {
  const auto target_before_sample =
      static_cast<std::int64_t>(std::lround(sample_point * tq_per_bit));
  std::int64_t tseg1 =
      std::clamp<std::int64_t>(target_before_sample - 1, limits.tseg1_min, limits.tseg1_max);
  std::int64_t tseg2 = std::int64_t{tq_per_bit} - 1 - tseg1;
  if (tseg2 < limits.tseg2_min) tseg2 = limits.tseg2_min;
  if (tseg2 > limits.tseg2_max) tseg2 = limits.tseg2_max;
  tseg1 = std::int64_t{tq_per_bit} - 1 - tseg2;
  if (tseg1 < limits.tseg1_min || tseg1 > limits.tseg1_max) return std::nullopt;
  return SegmentSplit{static_cast<std::uint32_t>(tseg1), static_cast<std::uint32_t>(tseg2)};
}

GsUsbBitTiming TimingFromSplit(const SegmentSplit& split, std::uint32_t brp,
                               std::uint32_t sjw_max) {
  GsUsbBitTiming timing;
  // The controller only sees the sum; halving it the way Linux does keeps logs comparable.
  timing.prop_seg = split.tseg1 / 2;
  timing.phase_seg1 = split.tseg1 - timing.prop_seg;
  timing.phase_seg2 = split.tseg2;
  // Linux's default SJW: half of phase_seg2, at least 1, and what the controller allows.
  timing.sjw = std::clamp<std::uint32_t>(split.tseg2 / 2, 1, std::max<std::uint32_t>(sjw_max, 1));
  timing.brp = brp;
  return timing;
}

CanFrame FrameFromWire(std::uint32_t can_id, std::uint8_t dlc, std::uint8_t flags,
                       std::span<const std::uint8_t> data) {
  CanFrame frame;
  frame.extended = (can_id & kCanEffFlag) != 0;
  frame.remote = (can_id & kCanRtrFlag) != 0;
  frame.error = (can_id & kCanErrFlag) != 0;
  frame.id = can_id & (frame.extended || frame.error ? kCanEffMask : kCanSffMask);
  frame.fd = (flags & gs_usb_frame_flag::kFd) != 0;
  frame.bitrate_switch = (flags & gs_usb_frame_flag::kBitrateSwitch) != 0;
  frame.error_state_indicator = (flags & gs_usb_frame_flag::kErrorStateIndicator) != 0;
  frame.length = static_cast<std::uint8_t>(LengthFromDlc(dlc & 0x0F, frame.fd));
  if (!frame.remote) std::copy_n(data.begin(), frame.length, frame.data.begin());
  return frame;
}

}  // namespace

std::array<std::uint8_t, kGsUsbHostConfigBytes> EncodeGsUsbHostFormat() {
  std::array<std::uint8_t, kGsUsbHostConfigBytes> out{};
  PutU32(out, 0, kGsUsbHostFormat);
  return out;
}

std::array<std::uint8_t, kGsUsbDeviceConfigBytes> EncodeGsUsbDeviceConfig(
    const GsUsbDeviceConfig& config) {
  std::array<std::uint8_t, kGsUsbDeviceConfigBytes> out{};
  out[3] = config.icount;
  PutU32(out, 4, config.sw_version);
  PutU32(out, 8, config.hw_version);
  return out;
}

Result<GsUsbDeviceConfig> DecodeGsUsbDeviceConfig(std::span<const std::uint8_t> bytes) {
  if (auto size = ExpectSize(bytes, kGsUsbDeviceConfigBytes, "device config"); !size) {
    return size.error();
  }
  return GsUsbDeviceConfig{bytes[3], GetU32(bytes, 4), GetU32(bytes, 8)};
}

std::array<std::uint8_t, kGsUsbBtConstBytes> EncodeGsUsbBtConst(const GsUsbBtConst& bt_const) {
  std::array<std::uint8_t, kGsUsbBtConstBytes> out{};
  PutU32(out, 0, bt_const.features);
  PutU32(out, 4, bt_const.fclk_can_hz);
  PutLimits(out, 8, bt_const.nominal);
  return out;
}

std::array<std::uint8_t, kGsUsbBtConstExtBytes> EncodeGsUsbBtConstExt(
    const GsUsbBtConst& bt_const) {
  HILRIG_CHECK(bt_const.data.has_value(), "BT_CONST_EXT needs the data-phase limits");
  std::array<std::uint8_t, kGsUsbBtConstExtBytes> out{};
  const std::array<std::uint8_t, kGsUsbBtConstBytes> base = EncodeGsUsbBtConst(bt_const);
  std::copy(base.begin(), base.end(), out.begin());
  PutLimits(out, kGsUsbBtConstBytes, *bt_const.data);
  return out;
}

Result<GsUsbBtConst> DecodeGsUsbBtConst(std::span<const std::uint8_t> bytes) {
  if (auto size = ExpectSize(bytes, kGsUsbBtConstBytes, "BT_CONST"); !size) return size.error();
  GsUsbBtConst bt_const;
  bt_const.features = GetU32(bytes, 0);
  bt_const.fclk_can_hz = GetU32(bytes, 4);
  bt_const.nominal = GetLimits(bytes, 8);
  return bt_const;
}

Result<GsUsbBtConst> DecodeGsUsbBtConstExt(std::span<const std::uint8_t> bytes) {
  if (auto size = ExpectSize(bytes, kGsUsbBtConstExtBytes, "BT_CONST_EXT"); !size) {
    return size.error();
  }
  Result<GsUsbBtConst> bt_const = DecodeGsUsbBtConst(bytes.first(kGsUsbBtConstBytes));
  if (!bt_const) return bt_const.error();
  bt_const.value().data = GetLimits(bytes, kGsUsbBtConstBytes);
  return bt_const;
}

double GsUsbBitTiming::sample_point() const {
  return static_cast<double>(1 + prop_seg + phase_seg1) / tq_per_bit();
}

double GsUsbBitTiming::bitrate_bps(std::uint32_t fclk_can_hz) const {
  return static_cast<double>(fclk_can_hz) / (static_cast<double>(brp) * tq_per_bit());
}

std::array<std::uint8_t, kGsUsbBitTimingBytes> EncodeGsUsbBitTiming(const GsUsbBitTiming& timing) {
  std::array<std::uint8_t, kGsUsbBitTimingBytes> out{};
  PutU32(out, 0, timing.prop_seg);
  PutU32(out, 4, timing.phase_seg1);
  PutU32(out, 8, timing.phase_seg2);
  PutU32(out, 12, timing.sjw);
  PutU32(out, 16, timing.brp);
  return out;
}

Result<GsUsbBitTiming> DecodeGsUsbBitTiming(std::span<const std::uint8_t> bytes) {
  if (auto size = ExpectSize(bytes, kGsUsbBitTimingBytes, "bit timing"); !size) {
    return size.error();
  }
  return GsUsbBitTiming{GetU32(bytes, 0), GetU32(bytes, 4), GetU32(bytes, 8), GetU32(bytes, 12),
                        GetU32(bytes, 16)};
}

Result<GsUsbBitTiming> CalculateGsUsbBitTiming(std::int64_t bitrate_bps, std::uint32_t fclk_can_hz,
                                               const GsUsbTimingLimits& limits,
                                               double sample_point) {
  if (bitrate_bps <= 0 || fclk_can_hz == 0) {
    return MakeError("gs_usb bit timing: bitrate and clock must be positive");
  }
  const std::uint32_t min_tq = 1 + limits.tseg1_min + limits.tseg2_min;
  const std::uint32_t max_tq = 1 + limits.tseg1_max + limits.tseg2_max;
  const std::uint32_t brp_step = std::max<std::uint32_t>(limits.brp_inc, 1);
  std::optional<GsUsbBitTiming> best;
  double best_rate_error = 0;
  double best_sample_error = 0;
  for (std::uint64_t brp = std::max<std::uint32_t>(limits.brp_min, 1); brp <= limits.brp_max;
       brp += brp_step) {
    const double exact_tq =
        static_cast<double>(fclk_can_hz) / (brp * static_cast<double>(bitrate_bps));
    const auto tq = static_cast<std::uint32_t>(std::lround(exact_tq));
    if (tq < min_tq) break;  // a larger prescaler only gives fewer quanta
    if (tq > max_tq) continue;
    const double rate_error =
        std::abs(static_cast<double>(fclk_can_hz) / (brp * tq) - bitrate_bps) / bitrate_bps;
    if (rate_error > kGsUsbMaxBitrateError) continue;
    const std::optional<SegmentSplit> split = SplitSegments(tq, limits, sample_point);
    if (!split) continue;
    const GsUsbBitTiming timing =
        TimingFromSplit(*split, static_cast<std::uint32_t>(brp), limits.sjw_max);
    const double sample_error = std::abs(timing.sample_point() - sample_point);
    const bool better =
        !best || rate_error < best_rate_error - 1e-12 ||
        (rate_error <= best_rate_error + 1e-12 && sample_error < best_sample_error - 1e-12);
    if (better) {
      best = timing;
      best_rate_error = rate_error;
      best_sample_error = sample_error;
    }
  }
  if (!best) {
    return MakeError("gs_usb bit timing: " + std::to_string(bitrate_bps) +
                     " bit/s cannot be reached within 0.5 % from a " + std::to_string(fclk_can_hz) +
                     " Hz CAN clock");
  }
  return *best;
}

std::array<std::uint8_t, kGsUsbModeBytes> EncodeGsUsbMode(const GsUsbMode& mode) {
  std::array<std::uint8_t, kGsUsbModeBytes> out{};
  PutU32(out, 0, mode.mode);
  PutU32(out, 4, mode.flags);
  return out;
}

Result<GsUsbMode> DecodeGsUsbMode(std::span<const std::uint8_t> bytes) {
  if (auto size = ExpectSize(bytes, kGsUsbModeBytes, "mode"); !size) return size.error();
  return GsUsbMode{GetU32(bytes, 0), GetU32(bytes, 4)};
}

std::size_t GsUsbHostFrameBytes(bool fd, bool with_timestamp) {
  return kGsUsbHostFrameHeaderBytes +
         (fd ? CanFrame::kMaxFdPayload : CanFrame::kMaxClassicPayload) +
         (with_timestamp ? kGsUsbTimestampBytes : 0);
}

std::vector<std::uint8_t> EncodeGsUsbHostFrame(const GsUsbHostFrame& host_frame) {
  const CanFrame& frame = host_frame.frame;
  HILRIG_CHECK(ValidateFrame(frame).ok(), "only valid frames can be encoded");
  std::vector<std::uint8_t> out(GsUsbHostFrameBytes(frame.fd, host_frame.timestamp_us.has_value()));
  std::uint32_t can_id = frame.id;
  if (frame.extended) can_id |= kCanEffFlag;
  if (frame.remote) can_id |= kCanRtrFlag;
  if (frame.error) can_id |= kCanErrFlag;
  PutU32(out, 0, host_frame.echo_id);
  PutU32(out, 4, can_id);
  out[8] = DlcFromLength(frame.length);
  out[9] = host_frame.channel;
  std::uint8_t flags = host_frame.overflow ? gs_usb_frame_flag::kOverflow : 0;
  if (frame.fd) flags |= gs_usb_frame_flag::kFd;
  if (frame.bitrate_switch) flags |= gs_usb_frame_flag::kBitrateSwitch;
  if (frame.error_state_indicator) flags |= gs_usb_frame_flag::kErrorStateIndicator;
  out[10] = flags;
  const std::span<const std::uint8_t> payload = frame.payload();
  std::copy(payload.begin(), payload.end(), out.begin() + kGsUsbHostFrameHeaderBytes);
  if (host_frame.timestamp_us) {
    PutU32(out, out.size() - kGsUsbTimestampBytes, *host_frame.timestamp_us);
  }
  return out;
}

Result<GsUsbHostFrame> DecodeGsUsbHostFrame(std::span<const std::uint8_t> bytes,
                                            bool timestamps_on) {
  if (bytes.size() < kGsUsbHostFrameHeaderBytes) {
    return MakeError("gs_usb host frame: " + std::to_string(bytes.size()) +
                     " bytes is shorter than the header");
  }
  const std::uint8_t flags = bytes[10];
  const bool fd = (flags & gs_usb_frame_flag::kFd) != 0;
  const std::size_t needed = GsUsbHostFrameBytes(fd, timestamps_on);
  if (bytes.size() < needed) {
    return MakeError("gs_usb host frame: " + std::to_string(bytes.size()) + " bytes, " +
                     std::to_string(needed) + " needed");
  }
  GsUsbHostFrame host_frame;
  host_frame.echo_id = GetU32(bytes, 0);
  host_frame.channel = bytes[9];
  host_frame.overflow = (flags & gs_usb_frame_flag::kOverflow) != 0;
  host_frame.frame =
      FrameFromWire(GetU32(bytes, 4), bytes[8], flags, bytes.subspan(kGsUsbHostFrameHeaderBytes));
  if (timestamps_on) host_frame.timestamp_us = GetU32(bytes, needed - kGsUsbTimestampBytes);
  if (Result<void> valid = ValidateFrame(host_frame.frame); !valid) {
    return MakeError("gs_usb host frame: " + valid.error().message);
  }
  return host_frame;
}

GsUsbUnwrappedTime UnwrapGsUsbTimestamp(GsUsbTimestampUnwrapper state, std::uint32_t timestamp_us) {
  if (!state.started) {
    state.started = true;
    state.last_extended_us = timestamp_us;
  } else {
    // Modular difference read as signed: a wrap is a small forward step, a reorder a small back.
    const auto delta_us = static_cast<std::int32_t>(timestamp_us - state.last_us);
    state.last_extended_us += delta_us;
  }
  state.last_us = timestamp_us;
  return GsUsbUnwrappedTime{state, state.last_extended_us * 1000};
}

}  // namespace hilrig::rig
