// The DUT's side of the HIL link on a line (proto/hil_link.proto, docs/serial_link.md), for any
// controller (dut_link/controller.h): the same code on the STM32 image, in dut_emu --serial and in
// a team's own DUT (examples/hover_dut). The platform feeds every byte of the link line to
// OnLinkByte; the session answers the runner's Hello (or, on a protocol version it does not speak,
// says Bye), hands the DutConfig that follows to the controller's Configure (answered by
// TargetInfo, or by Bye with the reason when refused), and then answers each SerialStep with a
// SerialCommand: the step's inputs in order into the controller, then the sensor-node frames the
// step announces read off the bridge line and stamped with the step's time, then one control step.
// A tick asked again (its answer was lost) is answered from the last output without stepping; a
// runner's Bye, or a new Hello, starts over. What it counts goes back with the commands.
//
// The platform provides four small interfaces, so a board and a host process plug in alike: the
// sink its frames are written to, the bridge line's bytes, a clock that bounds the wait for bridge
// bytes, and the cycle counter the work per step is measured with. Portable: the standard library
// only, fixed buffers (about 5 KB), no allocation, no exceptions. OnLinkByte cannot fail (what is
// wrong on the line is counted or answered with Bye); it is O(1) per byte, and O(message + bridge
// bytes) plus one control step at the byte that completes a frame.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "dut_link/controller.h"
#include "dut_link/line_framing.h"
#include "dut_link/run_description.h"
#include "dut_link/wire_codec.h"
#include "proto/hil_link_tags.h"
#include "protocol/uart_bridge.h"

namespace hilrig::dut_link {

// The HIL link's protocol version, proto/hil_link.proto's LinkProtocol (as the host's
// kHilLinkProtocolVersion).
inline constexpr std::uint32_t kSerialLinkProtocolVersion =
    proto_tags::LinkProtocol::kLinkProtocolVersion;
// How long the bridge line may stay quiet before the announced bytes count as lost. Generous on
// purpose: a board emulated under QEMU reads this clock in virtual time while QEMU's I/O thread,
// starved on a busy host, can hold the bytes back for tens of milliseconds, and a lockstep step
// taken without them is no longer the lockstep trace. A byte really lost costs one such wait,
// still well inside the host's answer timeout (1 s).
inline constexpr std::int64_t kBridgeGapNs = 250'000'000;

// Where the session's frames go (the link line's transmitter). Gets whole frames.
class LineSink {
 public:
  virtual void Write(std::span<const std::uint8_t> bytes) = 0;

 protected:
  ~LineSink() = default;
};

// The bridge line's received bytes; nullopt when none is waiting. Never blocks.
class ByteSource {
 public:
  virtual std::optional<std::uint8_t> ReadByte() = 0;

 protected:
  ~ByteSource() = default;
};

// Monotonic time of the DUT's own, for the bridge wait only (never for the control step).
class MonotonicClock {
 public:
  virtual std::int64_t NowNs() = 0;

 protected:
  ~MonotonicClock() = default;
};

// Free-running cycle counter; differences modulo 2^32 are the work measured.
class CycleCounter {
 public:
  virtual std::uint32_t Cycles() = 0;

 protected:
  ~CycleCounter() = default;
};

// What TargetInfo and Hello tell the runner about this DUT.
struct TargetDescription {
  std::string_view name;   // Hello.name, e.g. "dut_fw stm32f405"
  std::string_view board;  // TargetInfo.board
  std::uint32_t core_clock_hz = 0;
  std::uint32_t flash_used_bytes = 0;
  std::uint32_t ram_used_bytes = 0;
  std::uint32_t stack_bytes = 0;
  // What a DUT that dials the rig over TCP proves itself with (the rig's link token, 16 bytes);
  // empty on a serial line, where the wire itself is the proof.
  std::span<const std::uint8_t> link_token;
};

// proto SerialDutCounters, field for field.
struct SerialDutCounterValues {
  std::uint64_t frames_received = 0;
  std::uint64_t frames_bad_checksum = 0;
  std::uint64_t frames_malformed = 0;
  std::uint64_t frames_oversize = 0;
  std::uint64_t steps_repeated = 0;
  std::uint64_t steps_skipped = 0;
  std::uint64_t bridge_frames = 0;
  std::uint64_t bridge_bad_frames = 0;
  std::uint64_t bridge_bytes_missing = 0;
  std::uint64_t uart_overruns = 0;
  std::uint64_t rx_ring_drops = 0;

  friend constexpr bool operator==(const SerialDutCounterValues&,
                                   const SerialDutCounterValues&) = default;
};

enum class SerialDutPhase : std::uint8_t { kAwaitHello, kAwaitConfig, kRunning };

namespace serial_link_internal {

// The largest message the DUT sends: a SerialCommand with every field is about 170 bytes.
inline constexpr std::size_t kMaxReplyBytes = 320;

// Decimal text of `value` at the end of `out`; returns the digits. For reasons, without printf.
inline std::string_view Decimal(std::uint64_t value, std::array<char, 20>& out) {
  std::size_t at = out.size();
  do {
    out[--at] = char('0' + value % 10);
    value /= 10;
  } while (value != 0);
  return {out.data() + at, out.size() - at};
}

// Times from the wire are added in unsigned arithmetic: a tick or an offset no run reaches wraps
// instead of overflowing.
constexpr std::int64_t WrappingAdd(std::int64_t a, std::int64_t b) {
  return std::int64_t(std::uint64_t(a) + std::uint64_t(b));
}

inline std::span<const std::uint8_t> Bytes(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

// The inputs of one SerialStep, read in two passes: the first checks every input (a step that
// does not parse changes nothing), the second feeds them to the controller.
struct StepFields {
  std::uint64_t tick = 0;
  std::int64_t now_offset_ns = 0;
  std::uint32_t bridge_bytes = 0;
  bool realtime = false;
};

}  // namespace serial_link_internal

class SerialDutSession {
 public:
  // Every reference must outlive the session. Does not allocate.
  SerialDutSession(Controller& controller, LineSink& link, ByteSource& bridge,
                   MonotonicClock& clock, CycleCounter& cycles, const TargetDescription& target)
      : controller_(controller),
        link_(link),
        bridge_(bridge),
        clock_(clock),
        cycles_(cycles),
        target_(target) {}

  // Every byte received on the link line, in order. A complete frame is handled at once: the
  // answer is written to the sink before this returns (a step may first wait for bridge bytes,
  // at most kBridgeGapNs after the last one arrived).
  void OnLinkByte(std::uint8_t byte) {
    if (const auto payload = frames_.Feed(byte)) OnMessage(*payload);
  }

  // Bytes the platform's receivers lost before the session saw them (totals so far).
  void SetReceiveLosses(std::uint64_t uart_overruns, std::uint64_t rx_ring_drops) {
    uart_overruns_ = uart_overruns;
    rx_ring_drops_ = rx_ring_drops;
  }

  SerialDutPhase phase() const { return phase_; }
  SerialDutCounterValues counters() const {
    SerialDutCounterValues c;
    const FrameDecoderCounters& frames = frames_.counters();
    c.frames_received = frames.frames;
    c.frames_bad_checksum = frames.bad_checksums;
    c.frames_malformed = frames.malformed + messages_malformed_;
    c.frames_oversize = frames.oversize;
    c.steps_repeated = steps_repeated_;
    c.steps_skipped = steps_skipped_;
    const tactile_bus::UartDecoderCounters& bridge = bridge_frames_.counters();
    c.bridge_frames = bridge.frames;
    c.bridge_bad_frames = bridge.bad_checksums + bridge.bad_lengths + bridge.bad_ids;
    c.bridge_bytes_missing = bridge_bytes_missing_;
    c.uart_overruns = uart_overruns_;
    c.rx_ring_drops = rx_ring_drops_;
    return c;
  }

 private:
  using Reader = wire::Reader;
  using Writer = wire::Writer;

  void OnMessage(std::span<const std::uint8_t> payload) {
    namespace in = serial_link_internal;
    const std::uint32_t start_cycles = cycles_.Cycles();
    Reader message(payload);
    std::uint32_t kind = 0;
    std::span<const std::uint8_t> body;
    while (const auto tag = message.Next()) {
      if (tag->type != wire::WireType::kLengthDelimited) continue;  // not a payload of ours
      kind = tag->field;
      body = message.Bytes();
    }
    if (!message.ok()) {
      ++messages_malformed_;
      return;
    }
    switch (kind) {
      case proto_tags::LinkMessage::kHello:
        return OnHello(body);
      case proto_tags::LinkMessage::kConfig:
        return OnConfig(body);
      case proto_tags::LinkMessage::kBye:
        return Reset(SerialDutPhase::kAwaitHello);
      case proto_tags::LinkMessage::kSerialStep:
        return OnStep(body, start_cycles);
      default:
        return;  // messages for a DUT on TCP, or from a newer runner: not ours to answer
    }
  }

  void Reset(SerialDutPhase phase) {
    phase_ = phase;
    last_tick_.reset();
  }

  void OnHello(std::span<const std::uint8_t> body) {
    Reader hello(body);
    std::uint64_t version = 0;
    std::uint64_t role = 0;
    while (const auto tag = hello.Next()) {
      if (tag->field == proto_tags::Hello::kHeader) version = HeaderVersion(hello.Message());
      if (tag->field == proto_tags::Hello::kRole) role = hello.Varint();
    }
    if (!hello.ok() || role != proto_tags::Hello::Role::kRunner) {
      ++messages_malformed_;
      return;
    }
    sequence_ = 0;
    if (version != kSerialLinkProtocolVersion) {
      std::array<char, 20> theirs;
      std::array<char, 20> ours;
      SendBye("protocol version ", serial_link_internal::Decimal(version, theirs),
              ", this DUT speaks ",
              serial_link_internal::Decimal(kSerialLinkProtocolVersion, ours));
      return Reset(SerialDutPhase::kAwaitHello);
    }
    Reset(SerialDutPhase::kAwaitConfig);
    Writer w = BeginReply();
    const auto nested = w.BeginMessage(proto_tags::LinkMessage::kHello);
    PutHeader(w);
    w.Varint(proto_tags::Hello::kRole, proto_tags::Hello::Role::kDut);
    if (!target_.name.empty())
      w.Bytes(proto_tags::Hello::kName, serial_link_internal::Bytes(target_.name));
    if (!target_.link_token.empty()) w.Bytes(proto_tags::Hello::kToken, target_.link_token);
    w.EndMessage(nested);
    SendReply(w);
  }

  static std::uint64_t HeaderVersion(Reader header) {
    std::uint64_t version = 0;
    while (const auto tag = header.Next()) {
      if (tag->field == proto_tags::LinkHeader::kProtocolVersion) version = header.Varint();
    }
    return version;
  }

  void OnConfig(std::span<const std::uint8_t> body) {
    if (phase_ == SerialDutPhase::kAwaitHello) {
      return SendBye("dut config before hello", {}, {}, {});
    }
    RunDescription run;
    if (!DecodeRunDescription(body, run)) {
      SendBye("dut config is not a well-formed message", {}, {}, {});
      return Reset(SerialDutPhase::kAwaitHello);
    }
    const char* refusal = controller_.Configure(run);
    if (refusal == nullptr && !(run.control_period_s > 0 && std::isfinite(run.control_period_s))) {
      refusal = "dut config control period must be positive and finite";
    }
    if (refusal != nullptr) {
      SendBye(refusal, {}, {}, {});
      return Reset(SerialDutPhase::kAwaitHello);
    }
    setpoint_ = Setpoint{};  // the controller starts from the zero setpoint too
    period_ns_ = std::llround(run.control_period_s * 1e9);
    last_tick_.reset();
    phase_ = SerialDutPhase::kRunning;
    Writer w = BeginReply();
    namespace info = proto_tags::TargetInfo;
    const auto nested = w.BeginMessage(proto_tags::LinkMessage::kTargetInfo);
    PutHeader(w);
    if (!target_.board.empty()) w.Bytes(info::kBoard, serial_link_internal::Bytes(target_.board));
    w.NonZeroVarint(info::kCoreClockHz, target_.core_clock_hz);
    w.NonZeroVarint(info::kFlashUsedBytes, target_.flash_used_bytes);
    w.NonZeroVarint(info::kRamUsedBytes, target_.ram_used_bytes);
    w.NonZeroVarint(info::kStackBytes, target_.stack_bytes);
    w.EndMessage(nested);
    SendReply(w);
  }

  void OnStep(std::span<const std::uint8_t> body, std::uint32_t start_cycles) {
    if (phase_ != SerialDutPhase::kRunning) {
      return SendBye("serial step before an accepted dut config", {}, {}, {});
    }
    serial_link_internal::StepFields step;
    if (!ReadStep(body, step, false, 0)) {
      ++messages_malformed_;
      return;
    }
    if (last_tick_ && step.tick <= *last_tick_) {
      if (step.tick < *last_tick_) return;  // a stale copy overtaken by a later tick
      ++steps_repeated_;
      SendCommand(*last_tick_, last_output_, last_work_cycles_);
      return;
    }
    if (last_tick_) steps_skipped_ += step.tick - *last_tick_ - 1;
    const std::int64_t now_ns = serial_link_internal::WrappingAdd(
        std::int64_t(step.tick * std::uint64_t(period_ns_)), step.now_offset_ns);
    ReadStep(body, step, true, now_ns);
    std::uint32_t work_cycles = cycles_.Cycles() - start_cycles;
    work_cycles += DrainBridge(step, now_ns);
    const std::uint32_t step_start = cycles_.Cycles();
    last_output_ = controller_.Step(now_ns);
    last_tick_ = step.tick;
    last_work_cycles_ = SendCommand(step.tick, last_output_, work_cycles, step_start);
  }

  // Reads a SerialStep; with `apply` false only checks it, with true feeds its inputs to the core.
  bool ReadStep(std::span<const std::uint8_t> body, serial_link_internal::StepFields& step,
                bool apply, std::int64_t now_ns) {
    Reader r(body);
    bool inputs_ok = true;
    namespace serial_step = proto_tags::SerialStep;
    while (const auto tag = r.Next()) {
      switch (tag->field) {
        case serial_step::kTick:
          step.tick = r.Varint();
          break;
        case serial_step::kNowOffsetNs:
          step.now_offset_ns = r.SInt64();
          break;
        case serial_step::kInputs:
          inputs_ok = ReadInput(r.Message(), apply, now_ns) && inputs_ok;
          break;
        case serial_step::kBridgeBytes:
          step.bridge_bytes = r.Uint32();
          break;
        case serial_step::kRealtime:
          step.realtime = r.Bool();
          break;
        default:
          break;
      }
    }
    return r.ok() && inputs_ok;
  }

  bool ReadInput(Reader input, bool apply, std::int64_t now_ns) {
    bool ok = true;
    while (const auto tag = input.Next()) {
      if (tag->field == proto_tags::SerialInput::kImu)
        ok = ReadImu(input.Message(), apply, now_ns) && ok;
      if (tag->field == proto_tags::SerialInput::kVio)
        ok = ReadVio(input.Message(), apply, now_ns) && ok;
      if (tag->field == proto_tags::SerialInput::kSetpoint)
        ok = ReadSetpoint(input.Message(), apply) && ok;
    }
    return input.ok() && ok;
  }

  bool ReadImu(Reader imu, bool apply, std::int64_t now_ns) {
    std::array<float, 6> values{};
    std::size_t count = 0;
    std::int64_t offset_ns = 0;
    while (const auto tag = imu.Next()) {
      if (tag->field == proto_tags::SerialImu::kGyroAccel) imu.AppendFloats(values, count);
      if (tag->field == proto_tags::SerialImu::kTimeOffsetNs) offset_ns = imu.SInt64();
    }
    if (!imu.ok() || count != values.size()) return false;
    if (apply) {
      controller_.OnImu({{values[0], values[1], values[2]},
                         {values[3], values[4], values[5]},
                         serial_link_internal::WrappingAdd(now_ns, offset_ns)});
    }
    return true;
  }

  bool ReadVio(Reader vio, bool apply, std::int64_t now_ns) {
    std::array<float, 3> position{};
    std::array<float, 4> wxyz{};
    std::size_t position_count = 0;
    std::size_t wxyz_count = 0;
    std::int64_t offset_ns = 0;
    while (const auto tag = vio.Next()) {
      if (tag->field == proto_tags::SerialVio::kCaptureOffsetNs) offset_ns = vio.SInt64();
      if (tag->field == proto_tags::SerialVio::kPositionM)
        vio.AppendFloats(position, position_count);
      if (tag->field == proto_tags::SerialVio::kOrientationWxyz) vio.AppendFloats(wxyz, wxyz_count);
    }
    if (!vio.ok() || position_count != 3 || wxyz_count != 4) return false;
    if (apply) {
      controller_.OnVio({position, wxyz, serial_link_internal::WrappingAdd(now_ns, offset_ns)});
    }
    return true;
  }

  bool ReadSetpoint(Reader setpoint, bool apply) {
    std::array<Vec3f, 3> vectors{};
    std::array<std::size_t, 3> counts{};
    Setpoint next = setpoint_;
    namespace setpoint_field = proto_tags::SerialSetpoint;
    // The three vectors are fields one after the other: position, velocity, acceleration.
    static_assert(setpoint_field::kVelocityMS == setpoint_field::kPositionM + 1 &&
                  setpoint_field::kAccelerationMS2 == setpoint_field::kPositionM + 2);
    while (const auto tag = setpoint.Next()) {
      switch (tag->field) {
        case setpoint_field::kPositionM:
        case setpoint_field::kVelocityMS:
        case setpoint_field::kAccelerationMS2: {
          const std::uint32_t vector = tag->field - setpoint_field::kPositionM;
          setpoint.AppendFloats(vectors[vector], counts[vector]);
          break;
        }
        case setpoint_field::kYawRad:
          next.yaw_rad = setpoint.Float();
          break;
        case setpoint_field::kGraspRegulate:
          next.grasp_regulate = setpoint.Bool();
          break;
        case setpoint_field::kGraspForceN:
          next.grasp_force_n = setpoint.Float();
          break;
        case setpoint_field::kGraspReferenceAngleRad:
          next.grasp_reference_angle_rad = setpoint.Float();
          break;
        default:
          break;
      }
    }
    if (!setpoint.ok()) return false;
    Vec3f* targets[3] = {&next.position_m, &next.velocity_m_s, &next.acceleration_m_s2};
    for (std::size_t i = 0; i < 3; ++i) {  // a vector is absent (kept) or has all three values
      if (counts[i] != 0 && counts[i] != 3) return false;
      if (counts[i] == 3) *targets[i] = vectors[i];
    }
    if (apply) {
      setpoint_ = next;
      controller_.OnSetpoint(setpoint_);
    }
    return true;
  }

  // Feeds the bridge line's bytes to the tactile front end: in lockstep until the step's
  // announced bytes are in (or the line stays quiet for kBridgeGapNs: the rest counts as
  // missing), then whatever else is already there; in a real-time step only what is there.
  // Returns the cycles spent on the bytes, not on waiting for them.
  std::uint32_t DrainBridge(const serial_link_internal::StepFields& step, std::int64_t now_ns) {
    std::int64_t owed = step.realtime ? 0 : std::int64_t(step.bridge_bytes);
    // Bounds a line that never stops talking: the announced bytes plus a frame's worth.
    std::uint64_t budget = std::uint64_t(step.bridge_bytes) + tactile_bus::kUartMaxFrameBytes;
    // When the line went quiet; a flag and a value rather than an optional, which GCC cannot
    // always see is set before it is read once this is inlined.
    bool quiet = false;
    std::int64_t quiet_since_ns = 0;
    std::uint32_t work_cycles = 0;
    while (budget > 0) {
      const std::optional<std::uint8_t> byte = bridge_.ReadByte();
      if (byte) {
        const std::uint32_t start = cycles_.Cycles();
        --budget;
        --owed;
        quiet = false;
        OnBridgeByte(*byte, now_ns);
        work_cycles += cycles_.Cycles() - start;
        continue;
      }
      if (owed <= 0) break;
      const std::int64_t clock_ns = clock_.NowNs();
      if (!quiet) {
        quiet = true;
        quiet_since_ns = clock_ns;
      } else if (clock_ns - quiet_since_ns >= kBridgeGapNs) {
        bridge_bytes_missing_ += std::uint64_t(owed);
        break;
      }
    }
    return work_cycles;
  }

  void OnBridgeByte(std::uint8_t byte, std::int64_t now_ns) {
    const std::optional<tactile_bus::NodeFrame> frame = bridge_frames_.Feed(byte);
    if (!frame) return;
    controller_.OnCanFrame({frame->id, frame->len, frame->data, now_ns});
  }

  // Sends the command for `tick` and returns the work_cycles it carries: `work_cycles` plus, when
  // `since` is given, the cycles from then until the field is written (stepping and encoding are
  // part of the step's work).
  std::uint32_t SendCommand(std::uint64_t tick, const StepOutput& out, std::uint32_t work_cycles,
                            std::optional<std::uint32_t> since = std::nullopt) {
    Writer w = BeginReply();
    namespace command = proto_tags::SerialCommand;
    const auto nested = w.BeginMessage(proto_tags::LinkMessage::kSerialCommand);
    w.NonZeroVarint(command::kAnswersTick, tick);
    w.PackedFloats(command::kRotorThrustN, out.rotor_thrust_n);
    if (out.armed) w.Bool(command::kArmed, true);
    PutNonZeroFloat(w, command::kServoAngleRad, out.servo_angle_rad);
    w.PackedFloats(command::kEstimatedPositionM, out.estimated_position_m);
    if (out.tactile_ready) w.Bool(command::kTactileReady, true);
    PutNonZeroFloat(w, command::kGraspForceEstimateN, out.grasp_force_estimate_n);
    w.PackedFloats(command::kExternalForceWorldN, out.external_force_world_n);
    std::array<float, 18> pads{};
    bool any_pad = false;
    for (std::size_t i = 0; i < out.pad_force_sensor_n.size(); ++i) {
      for (std::size_t axis = 0; axis < 3; ++axis) {
        pads[3 * i + axis] = out.pad_force_sensor_n[i][axis];
        any_pad = any_pad || pads[3 * i + axis] != 0.f;
      }
    }
    if (any_pad) w.PackedFloats(command::kTactileForceSensorN, pads);
    if (since) work_cycles += cycles_.Cycles() - *since;
    w.NonZeroVarint(command::kWorkCycles, work_cycles);
    const SerialDutCounterValues now = counters();
    if (now != counters_sent_) {
      PutCounters(w, now);
      counters_sent_ = now;
    }
    w.EndMessage(nested);
    SendReply(w);
    return work_cycles;
  }

  static void PutCounters(Writer& w, const SerialDutCounterValues& c) {
    namespace counter = proto_tags::SerialDutCounters;
    const auto nested = w.BeginMessage(proto_tags::SerialCommand::kCounters);
    w.NonZeroVarint(counter::kFramesReceived, c.frames_received);
    w.NonZeroVarint(counter::kFramesBadChecksum, c.frames_bad_checksum);
    w.NonZeroVarint(counter::kFramesMalformed, c.frames_malformed);
    w.NonZeroVarint(counter::kFramesOversize, c.frames_oversize);
    w.NonZeroVarint(counter::kStepsRepeated, c.steps_repeated);
    w.NonZeroVarint(counter::kStepsSkipped, c.steps_skipped);
    w.NonZeroVarint(counter::kBridgeFrames, c.bridge_frames);
    w.NonZeroVarint(counter::kBridgeBadFrames, c.bridge_bad_frames);
    w.NonZeroVarint(counter::kBridgeBytesMissing, c.bridge_bytes_missing);
    w.NonZeroVarint(counter::kUartOverruns, c.uart_overruns);
    w.NonZeroVarint(counter::kRxRingDrops, c.rx_ring_drops);
    w.EndMessage(nested);
  }

  // proto3 leaves a field at its default off the wire; so does the DUT (as libprotobuf would).
  static void PutNonZeroFloat(Writer& w, std::uint32_t field, float value) {
    if (value != 0.f) w.Float(field, value);
  }

  void PutHeader(Writer& w) {
    const auto nested = w.BeginMessage(proto_tags::Hello::kHeader);  // every header is field 1
    w.Varint(proto_tags::LinkHeader::kProtocolVersion, kSerialLinkProtocolVersion);
    w.NonZeroVarint(proto_tags::LinkHeader::kSequence, sequence_++);
    w.EndMessage(nested);
  }

  // Bye{error, reason}, the reason the concatenation of up to four parts.
  void SendBye(std::string_view a, std::string_view b, std::string_view c, std::string_view d) {
    Writer w = BeginReply();
    const auto nested = w.BeginMessage(proto_tags::LinkMessage::kBye);
    PutHeader(w);
    w.Bool(proto_tags::Bye::kError, true);
    std::array<std::uint8_t, 128> reason{};
    std::size_t length = 0;
    for (const std::string_view part : {a, b, c, d}) {
      for (const char ch : part) {
        if (length < reason.size()) reason[length++] = std::uint8_t(ch);
      }
    }
    w.Bytes(proto_tags::Bye::kReason, std::span<const std::uint8_t>(reason.data(), length));
    w.EndMessage(nested);
    SendReply(w);
  }

  Writer BeginReply() { return Writer(reply_); }

  void SendReply(const Writer& w) {
    if (!w.ok()) return;  // cannot happen: kMaxReplyBytes holds every reply
    const std::size_t size = EncodeFrame(w.written(), frame_out_);
    if (size != 0) link_.Write(std::span<const std::uint8_t>(frame_out_.data(), size));
  }

  Controller& controller_;
  LineSink& link_;
  ByteSource& bridge_;
  MonotonicClock& clock_;
  CycleCounter& cycles_;
  TargetDescription target_;

  FrameDecoder<kMaxLineMessageBytes> frames_;
  tactile_bus::UartDecoder bridge_frames_;
  std::array<std::uint8_t, serial_link_internal::kMaxReplyBytes> reply_{};
  std::array<std::uint8_t, EncodedFrameBytes(serial_link_internal::kMaxReplyBytes)> frame_out_{};

  SerialDutPhase phase_ = SerialDutPhase::kAwaitHello;
  std::int64_t period_ns_ = 0;
  Setpoint setpoint_;
  std::optional<std::uint64_t> last_tick_;
  StepOutput last_output_;
  std::uint32_t last_work_cycles_ = 0;
  std::uint64_t sequence_ = 0;

  std::uint64_t messages_malformed_ = 0;
  std::uint64_t steps_repeated_ = 0;
  std::uint64_t steps_skipped_ = 0;
  std::uint64_t bridge_bytes_missing_ = 0;
  std::uint64_t uart_overruns_ = 0;
  std::uint64_t rx_ring_drops_ = 0;
  SerialDutCounterValues counters_sent_;
};

}  // namespace hilrig::dut_link
