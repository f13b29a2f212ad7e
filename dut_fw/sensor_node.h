// The firmware logic of one tactile sensor node (STM32F042 + MLX90393): when to sample, how a chip
// result becomes a sample frame, the 1 Hz status frame, the configuration commands, forwarding of
// frames from further down the daisy chain, and the UART bridge through which any one node streams
// every frame it sees. The wire layout is the tactile bus protocol of proto/TACTILE_PROTOCOL.md;
// rig/tactile_protocol.h is the host's codec for the same frames. Both take the protocol's numbers
// from protocol/tactile_bus.h, and tests/rig/tactile_protocol_test.cc decodes this node's frames
// with the rig codec.
//
// Like the rest of dut_fw this is portable C++ with no heap, no exceptions and no I/O: the MCU's
// main loop reads the chip and the CAN/UART peripherals and hands the results in, with the time of
// the event, so the same code runs on the node and in the host's emulated nodes and replays
// exactly. Frames are plain byte arrays (NodeFrame), not rig::CanFrame.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "dut_fw/mlx90393.h"
#include "protocol/tactile_bus.h"
#include "protocol/uart_bridge.h"

namespace hilrig::dut_fw {

// The bus's frames and their UART bridge form, as the node's firmware names them.
using tactile_bus::Crc8Atm;
using tactile_bus::EncodeUartFrame;
using tactile_bus::kUartMaxFrameBytes;
using tactile_bus::kUartSync0;
using tactile_bus::kUartSync1;
using tactile_bus::NodeFrame;
using tactile_bus::UartDecoder;
using tactile_bus::UartDecoderCounters;

constexpr std::optional<std::uint8_t> RateCodeFromHz(std::uint16_t rate_hz) {
  for (std::size_t code = 0; code < tactile_bus::kRateHzByCode.size(); ++code) {
    if (tactile_bus::kRateHzByCode[code] == rate_hz) return std::uint8_t(code);
  }
  return std::nullopt;
}

// Sample times k / rate_hz after the start, computed from the slot index rather than by adding a
// rounded period, so rates that do not divide a second into whole nanoseconds do not drift. The
// origin moves forward by exactly one second every rate_hz slots, which keeps the arithmetic
// small for any run length.
class SampleSchedule {
 public:
  static constexpr std::int64_t kNsPerSecond = 1'000'000'000;

  // (Re)starts at `now_ns`, with the first slot due at once; 0 Hz stops sampling.
  constexpr void Start(std::uint16_t rate_hz, std::int64_t now_ns) {
    rate_hz_ = rate_hz;
    origin_ns_ = now_ns;
    slot_ = 0;
    next_due_ns_ = SlotTimeNs();
  }

  constexpr std::uint16_t rate_hz() const { return rate_hz_; }
  constexpr bool Due(std::int64_t now_ns) const { return rate_hz_ != 0 && now_ns >= next_due_ns_; }
  constexpr std::int64_t NextDueNs() const { return next_due_ns_; }
  // No time before this is Due (INT64_MAX when stopped): a loop can sleep, or skip, until then.
  constexpr std::int64_t NextEventNs() const { return rate_hz_ == 0 ? INT64_MAX : next_due_ns_; }

  // Consumes every slot due at `now_ns` and returns how many there were: 1 when the loop keeps
  // up, more when it fell behind (the extra ones are skipped, not sent in a burst).
  constexpr std::uint32_t Consume(std::int64_t now_ns) {
    std::uint32_t consumed = 0;
    while (Due(now_ns)) {
      ++consumed;
      if (++slot_ == rate_hz_) {
        slot_ = 0;
        origin_ns_ += kNsPerSecond;
      }
      next_due_ns_ = SlotTimeNs();
    }
    return consumed;
  }

 private:
  // The division happens once per slot here rather than on every Due check of a polling loop.
  constexpr std::int64_t SlotTimeNs() const {
    return rate_hz_ == 0
               ? origin_ns_
               : origin_ns_ + std::int64_t(slot_ * std::uint64_t(kNsPerSecond) / rate_hz_);
  }

  std::uint16_t rate_hz_ = 0;
  std::int64_t origin_ns_ = 0;
  std::uint32_t slot_ = 0;
  std::int64_t next_due_ns_ = 0;  // SlotTimeNs() of the current slot
};

// A fixed-capacity FIFO of frames: forwarding must never block the node's own sampling, so when
// the upstream side cannot keep up the newest frame is dropped and counted.
template <std::size_t kCapacity>
class FrameQueue {
  static_assert(kCapacity > 0, "a forwarding queue needs at least one slot");

 public:
  constexpr bool Push(const NodeFrame& frame) {
    if (size_ == kCapacity) {
      if (drops_ != UINT32_MAX) ++drops_;
      return false;
    }
    slots_[(head_ + size_) % kCapacity] = frame;
    ++size_;
    return true;
  }

  constexpr std::optional<NodeFrame> Pop() {
    if (size_ == 0) return std::nullopt;
    const NodeFrame frame = slots_[head_];
    head_ = (head_ + 1) % kCapacity;
    --size_;
    return frame;
  }

  constexpr std::size_t size() const { return size_; }
  constexpr std::uint32_t drops() const { return drops_; }
  constexpr void Clear() {
    head_ = 0;
    size_ = 0;
    drops_ = 0;
  }

 private:
  std::array<NodeFrame, kCapacity> slots_{};
  std::size_t head_ = 0;
  std::size_t size_ = 0;
  std::uint32_t drops_ = 0;
};

// One completed X/Y/Z conversion as the node reads it: the result words and the ERROR bit of the
// chip's status byte.
struct ChipConversion {
  std::array<std::uint16_t, 3> code{};
  bool error = false;
};

// MLX90393 temperature word to 0.01 °C: 25 °C at 46244 LSB, 45.2 LSB/°C (datasheet typical
// values; the nodes do not trim them). Integer arithmetic, rounded to nearest, because the
// STM32F042 has no FPU.
constexpr std::int16_t ChipTemperatureCentiC(std::uint16_t temperature_word) {
  const std::int32_t delta = std::int32_t(temperature_word) - 46244;
  const std::int32_t scaled = delta * 1000;  // centi-°C = delta * 100 / 45.2 = delta * 1000 / 452
  const std::int32_t rounded = (scaled >= 0 ? scaled + 226 : scaled - 226) / 452;
  return std::int16_t(2500 + rounded);  // |rounded| <= 1024, so no overflow
}

// The sample frame of `node_id`: x, y, z little-endian, then sequence and status.
constexpr NodeFrame PackSampleFrame(std::uint8_t node_id, const std::array<std::uint16_t, 3>& code,
                                    std::uint8_t sequence, std::uint8_t status) {
  NodeFrame frame;
  frame.id = std::uint16_t(tactile_bus::kSampleBaseId + node_id);
  frame.len = 8;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    frame.data[2 * axis] = std::uint8_t(code[axis] & 0xFF);
    frame.data[2 * axis + 1] = std::uint8_t(code[axis] >> 8);
  }
  frame.data[6] = sequence;
  frame.data[7] = status;
  return frame;
}

// A sample frame as the receiving side takes it apart: what PackSampleFrame packed.
struct NodeSample {
  std::uint8_t node_id = 0;
  std::array<std::uint16_t, 3> code{};
  std::uint8_t sequence = 0;
  std::uint8_t status = 0;

  friend constexpr bool operator==(const NodeSample&, const NodeSample&) = default;
};

// The sample in `frame`; nullopt for every other frame (status, commands, other ids) and for a
// sample id with the wrong length, which rig/tactile_protocol.h rejects the same way.
constexpr std::optional<NodeSample> UnpackSampleFrame(const NodeFrame& frame) {
  if (frame.id < tactile_bus::kSampleBaseId + tactile_bus::kFirstNodeId ||
      frame.id > tactile_bus::kSampleBaseId + tactile_bus::kLastNodeId || frame.len != 8) {
    return std::nullopt;
  }
  NodeSample sample;
  sample.node_id = std::uint8_t(frame.id - tactile_bus::kSampleBaseId);
  for (std::size_t axis = 0; axis < 3; ++axis) {
    sample.code[axis] = std::uint16_t(frame.data[2 * axis] | (frame.data[2 * axis + 1] << 8));
  }
  sample.sequence = frame.data[6];
  sample.status = frame.data[7];
  return sample;
}

// True when any axis sits at a rail of the RES window it was converted at.
constexpr bool AnyAxisSaturated(const std::array<std::uint16_t, 3>& code, std::uint8_t resolution) {
  for (std::uint16_t word : code) {
    if (CountsSaturated(CodeToCounts(word, resolution), resolution)) return true;
  }
  return false;
}

// GAIN_SEL 7, RES 0: the chip's register defaults after power-on, before the node programs it.
inline constexpr Mlx90393Setting kMlx90393PowerOnSetting{7, 0};

struct NodeSettings {
  std::uint16_t rate_hz = 50;
  Mlx90393Setting chip{7, 0};  // GAIN_SEL 7 (most sensitive), RES 0: the rig's default
};

// The node's state machine. The main loop calls, in any order and as often as it likes:
//   SampleDue/TakeSample  -- when a slot is due, with the conversion the chip delivered (or
//                            nullopt when it did not answer in time);
//   StatusDue/TakeStatus  -- the 1 Hz status frame;
//   OnBusFrame            -- every frame received; commands for this node are handled here;
//   OnDownstreamFrame/PopForward -- the daisy chain;
//   config_pending/chip_setting/OnConfigApplied -- reprogramming the chip after a command.
template <std::size_t kForwardCapacity = 16>
class SensorNode {
 public:
  // `node_id` must be 1..7; the node starts sampling at once.
  constexpr SensorNode(std::uint8_t node_id, std::int64_t now_ns, NodeSettings defaults = {})
      : node_id_(node_id), defaults_(defaults) {
    Reset(now_ns);
  }

  constexpr std::uint8_t node_id() const { return node_id_; }
  constexpr std::uint16_t rate_hz() const { return sample_schedule_.rate_hz(); }
  // The setting the chip should run; equal to the one it runs unless config_pending().
  constexpr Mlx90393Setting chip_setting() const { return requested_; }
  constexpr bool config_pending() const {
    return requested_.gain_sel != applied_.gain_sel || requested_.resolution != applied_.resolution;
  }
  // The main loop wrote chip_setting() to the chip: data from now on is in that setting.
  constexpr void OnConfigApplied() { applied_ = requested_; }
  constexpr std::uint8_t rx_error_count() const { return rx_errors_; }
  constexpr std::uint32_t forward_drops() const { return forward_.drops(); }
  constexpr std::uint32_t skipped_slots() const { return skipped_slots_; }

  constexpr bool SampleDue(std::int64_t now_ns) const { return sample_schedule_.Due(now_ns); }

  // The sample frame of the slot due at `now_ns`. Without a conversion the node re-sends its last
  // good result marked stale, so the receiver keeps its timing and sees why the data did not move.
  // Slots the loop was too late for advance the sequence too, so they show as a gap upstream.
  // Call it when SampleDue(now_ns); called early it sends an extra frame without using a slot.
  constexpr NodeFrame TakeSample(std::int64_t now_ns,
                                 const std::optional<ChipConversion>& conversion) {
    const std::uint32_t slots = sample_schedule_.Consume(now_ns);
    if (slots > 1) {
      skipped_slots_ += slots - 1;
      sequence_ = std::uint8_t(sequence_ + (slots - 1));
    }
    chip_error_ = !conversion.has_value();
    std::array<std::uint16_t, 3> code = last_code_;
    std::uint8_t status = std::uint8_t(last_status_ | tactile_bus::kSampleStale);
    if (conversion) {
      code = conversion->code;  // as read, even when the chip flagged an error
      status = AnyAxisSaturated(code, applied_.resolution) ? tactile_bus::kSampleSaturated : 0;
      if (conversion->error) {
        status |= tactile_bus::kSampleConversionError;
      } else {
        last_code_ = code;
        last_status_ = status;
      }
    }
    if (tare_pending_) {
      status |= tactile_bus::kSampleTare;
      tare_pending_ = false;
    }
    return PackSampleFrame(node_id_, code, sequence_++, status);
  }

  // The chip's latest temperature, reported in the next status frame.
  constexpr void OnTemperature(std::int16_t temperature_centi_c) {
    temperature_centi_c_ = temperature_centi_c;
  }

  constexpr bool StatusDue(std::int64_t now_ns) const { return status_schedule_.Due(now_ns); }

  // Neither SampleDue nor StatusDue holds before this time; only TakeSample, TakeStatus and
  // OnBusFrame move it.
  constexpr std::int64_t NextEventNs() const {
    const std::int64_t sample_ns = sample_schedule_.NextEventNs();
    const std::int64_t status_ns = status_schedule_.NextEventNs();
    return sample_ns < status_ns ? sample_ns : status_ns;
  }
  constexpr NodeFrame TakeStatus(std::int64_t now_ns) {
    status_schedule_.Consume(now_ns);
    return MakeStatus();
  }

  // Every frame the node receives from the bus. Returns the status frame to send at once when the
  // frame was a command for this node or for all nodes (a rejected command answers too, with
  // kFlagCommandRejected, so the host learns about it without waiting a second).
  constexpr std::optional<NodeFrame> OnBusFrame(const NodeFrame& frame, std::int64_t now_ns) {
    if (frame.id != tactile_bus::kConfigBaseId &&
        frame.id != tactile_bus::kConfigBaseId + node_id_) {
      return std::nullopt;
    }
    command_rejected_ = !ApplyCommand(frame, now_ns);
    if (command_rejected_ && rx_errors_ != UINT8_MAX) ++rx_errors_;
    return MakeStatus();
  }

  // A frame from the next node down the chain, to be passed upstream. False when the queue was
  // full and the frame was dropped (counted, and flagged in the next status frame).
  constexpr bool OnDownstreamFrame(const NodeFrame& frame) {
    const bool queued = forward_.Push(frame);
    forward_overflow_ = forward_overflow_ || !queued;
    return queued;
  }
  constexpr std::optional<NodeFrame> PopForward() { return forward_.Pop(); }

 private:
  constexpr void Reset(std::int64_t now_ns) {
    requested_ = defaults_.chip;  // applied_ stays: a reset command does not power-cycle the chip
    sample_schedule_.Start(defaults_.rate_hz, now_ns);
    status_schedule_.Start(1, now_ns);
    sequence_ = 0;
    last_code_ = {};
    last_status_ = 0;
    rx_errors_ = 0;
    skipped_slots_ = 0;
    chip_error_ = false;
    command_rejected_ = false;
    tare_pending_ = false;
    forward_overflow_ = false;
    forward_.Clear();
  }

  // Length and argument checks happen before anything changes, so a rejected command has no
  // effect at all.
  constexpr bool ApplyCommand(const NodeFrame& frame, std::int64_t now_ns) {
    if (frame.len < tactile_bus::kConfigMinLength || frame.len > 8) return false;
    const std::uint8_t argument = frame.data[1];
    switch (frame.data[0]) {
      case tactile_bus::kCommandSetRate: {
        if (frame.len < 3) return false;
        const auto rate_hz = std::uint16_t(frame.data[1] | (frame.data[2] << 8));
        if (!RateCodeFromHz(rate_hz)) return false;
        sample_schedule_.Start(rate_hz, now_ns);
        return true;
      }
      case tactile_bus::kCommandSetGain:
        if (argument > kMlx90393MaxGainSel) return false;
        requested_.gain_sel = argument;
        return true;
      case tactile_bus::kCommandSetResolution:
        if (argument > kMlx90393MaxResolution) return false;
        requested_.resolution = argument;
        return true;
      case tactile_bus::kCommandZero:
        tare_pending_ = true;
        return true;
      case tactile_bus::kCommandReset:
        Reset(now_ns);
        return true;
      default:
        return false;
    }
  }

  constexpr std::uint8_t Flags() const {
    std::uint8_t flags = 0;
    if (chip_error_) flags |= tactile_bus::kFlagChipError;
    if (config_pending()) flags |= tactile_bus::kFlagConfigPending;
    if (command_rejected_) flags |= tactile_bus::kFlagCommandRejected;
    if (tare_pending_) flags |= tactile_bus::kFlagTarePending;
    if (forward_overflow_) flags |= tactile_bus::kFlagForwardOverflow;
    return flags;
  }

  // Reports the setting the data is in (the applied one) and clears the one-shot overflow flag.
  constexpr NodeFrame MakeStatus() {
    const Mlx90393Setting& reported = applied_;
    NodeFrame frame;
    frame.id = std::uint16_t(tactile_bus::kStatusBaseId + node_id_);
    frame.len = 8;
    const auto temperature_bits = std::uint16_t(temperature_centi_c_);
    frame.data = {std::uint8_t(temperature_bits & 0xFF),
                  std::uint8_t(temperature_bits >> 8),
                  Flags(),
                  reported.gain_sel,
                  reported.resolution,
                  RateCodeFromHz(sample_schedule_.rate_hz()).value_or(0),
                  rx_errors_,
                  tactile_bus::kFirmwareVersion};
    forward_overflow_ = false;
    return frame;
  }

  std::uint8_t node_id_;
  NodeSettings defaults_;
  Mlx90393Setting requested_{};
  Mlx90393Setting applied_ = kMlx90393PowerOnSetting;
  SampleSchedule sample_schedule_;
  SampleSchedule status_schedule_;
  std::uint8_t sequence_ = 0;
  std::array<std::uint16_t, 3> last_code_{};
  std::uint8_t last_status_ = 0;  // status bits of last_code_
  std::int16_t temperature_centi_c_ = 2500;
  std::uint8_t rx_errors_ = 0;
  std::uint32_t skipped_slots_ = 0;
  bool chip_error_ = false;
  bool command_rejected_ = false;
  bool tare_pending_ = false;
  bool forward_overflow_ = false;
  FrameQueue<kForwardCapacity> forward_;
};

}  // namespace hilrig::dut_fw
