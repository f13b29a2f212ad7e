#include "host/linked_dut/serial_dut_link.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "host/link/dut_config_codec.h"
#include "protocol/uart_bridge.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

constexpr int kLockstepWriteTimeoutMs = 1000;
constexpr int kByeTimeoutMs = 100;
// An emulator has nothing to save, and QEMU answers SIGTERM with a line on its stderr: it is
// killed at once.
constexpr int kEmulatorGraceMs = 0;

// Rounded up, so a wait never ends before its deadline.
int MillisecondsUntil(std::int64_t now_ns, std::int64_t deadline_ns) {
  return static_cast<int>(std::max<std::int64_t>(0, (deadline_ns - now_ns + 999'999) / 1'000'000));
}

template <typename Repeated>
void SetFloats(Repeated* out, std::initializer_list<double> values) {
  out->Clear();
  for (const double value : values) out->Add(static_cast<float>(value));
}

template <typename Repeated>
void SetVector(Repeated* out, const Eigen::Vector3d& vector) {
  SetFloats(out, {vector.x(), vector.y(), vector.z()});
}

proto::SerialSetpoint FullSetpoint(const SetpointMessage& setpoint) {
  proto::SerialSetpoint full;
  SetVector(full.mutable_position_m(), setpoint.position_m);
  SetVector(full.mutable_velocity_m_s(), setpoint.velocity_m_s);
  SetVector(full.mutable_acceleration_m_s2(), setpoint.acceleration_m_s2);
  full.set_yaw_rad(static_cast<float>(setpoint.yaw_rad));
  full.set_grasp_regulate(setpoint.grasp_regulate);
  full.set_grasp_force_n(static_cast<float>(setpoint.grasp_force_n));
  full.set_grasp_reference_angle_rad(static_cast<float>(setpoint.grasp_reference_angle_rad));
  return full;
}

template <typename Repeated>
bool SameFloats(const Repeated& a, const Repeated& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end());
}

// The fields of `full` that differ from `last` (all of them without a last).
proto::SerialSetpoint ChangedFields(const proto::SerialSetpoint& full,
                                    const std::optional<proto::SerialSetpoint>& last) {
  if (!last) return full;
  proto::SerialSetpoint changed;
  if (!SameFloats(full.position_m(), last->position_m())) {
    *changed.mutable_position_m() = full.position_m();
  }
  if (!SameFloats(full.velocity_m_s(), last->velocity_m_s())) {
    *changed.mutable_velocity_m_s() = full.velocity_m_s();
  }
  if (!SameFloats(full.acceleration_m_s2(), last->acceleration_m_s2())) {
    *changed.mutable_acceleration_m_s2() = full.acceleration_m_s2();
  }
  if (full.yaw_rad() != last->yaw_rad()) changed.set_yaw_rad(full.yaw_rad());
  if (full.grasp_regulate() != last->grasp_regulate()) {
    changed.set_grasp_regulate(full.grasp_regulate());
  }
  if (full.grasp_force_n() != last->grasp_force_n())
    changed.set_grasp_force_n(full.grasp_force_n());
  if (full.grasp_reference_angle_rad() != last->grasp_reference_angle_rad()) {
    changed.set_grasp_reference_angle_rad(full.grasp_reference_angle_rad());
  }
  return changed;
}

template <typename Repeated>
rig::Result<Eigen::Vector3d> Vector3From(const Repeated& values, const char* field) {
  if (values.size() != 3) {
    return rig::MakeError(std::string(field) + " has " + std::to_string(values.size()) +
                          " values, not 3");
  }
  return Eigen::Vector3d(values[0], values[1], values[2]);
}

rig::Result<ActuatorMessage> ActuatorFrom(const proto::SerialCommand& command,
                                          std::int64_t now_ns) {
  ActuatorMessage message;
  message.stamp = {command.answers_tick(), now_ns};
  message.answers_sequence = command.answers_tick();
  if (command.rotor_thrust_n_size() != 4) {
    return rig::MakeError("rotor_thrust_n has " + std::to_string(command.rotor_thrust_n_size()) +
                          " values, not 4");
  }
  for (int rotor = 0; rotor < 4; ++rotor)
    message.rotor_thrust_n[rotor] = command.rotor_thrust_n(rotor);
  message.armed = command.armed();
  auto position = Vector3From(command.estimated_position_m(), "estimated_position_m");
  if (!position) return position.error();
  message.estimated_position_m = position.value();
  auto external = Vector3From(command.external_force_world_n(), "external_force_world_n");
  if (!external) return external.error();
  message.external_force_world_n = external.value();
  const auto& forces = command.tactile_force_sensor_n();
  if (!forces.empty() && forces.size() != 18) {
    return rig::MakeError("tactile_force_sensor_n has " + std::to_string(forces.size()) +
                          " values, not 18 (or none)");
  }
  for (int node = 0; node < 6 && !forces.empty(); ++node) {
    message.tactile_force_sensor_n[node] =
        Eigen::Vector3d(forces[3 * node], forces[3 * node + 1], forces[3 * node + 2]);
  }
  message.tactile_ready = command.tactile_ready();
  message.servo_angle_rad = command.servo_angle_rad();
  message.grasp_force_estimate_n = command.grasp_force_estimate_n();
  return message;
}

// The sensor node frame a CAN frame carries, when the UART bridge can carry it.
std::optional<tactile_bus::NodeFrame> NodeFrameOf(const rig::TimedCanFrame& timed) {
  const rig::CanFrame& frame = timed.frame;
  if (timed.tx_echo || frame.extended || frame.remote || frame.error || frame.fd ||
      frame.length > 8) {
    return std::nullopt;
  }
  tactile_bus::NodeFrame node;
  node.id = static_cast<std::uint16_t>(frame.id);
  node.len = frame.length;
  std::copy_n(frame.data.begin(), frame.length, node.data.begin());
  return node;
}

}  // namespace

SerialDutLink::SerialDutLink(const DutFirmware& firmware, double control_period_s,
                             SerialLineOpener open_lines, const SerialDutOptions& options)
    : firmware_(firmware),
      control_period_s_(control_period_s),
      period_ns_(rig::NsFromSeconds(control_period_s)),
      open_lines_(std::move(open_lines)),
      options_(options),
      retry_ns_(rig::NsFromSeconds(options.step_retry_s)) {}

rig::Result<void> SerialDutLink::Open(const rig::Clock& clock) {
  if (auto valid = ValidateSerialDutOptions(options_); !valid) return valid.error();
  auto lines = open_lines_(options_.start_timeout_s);
  if (!lines) return lines.error();
  lines_ = std::move(lines).value();
  link_ = std::make_unique<LineLink>(*lines_.link);
  return Handshake(clock);
}

std::int64_t SerialDutLink::RetryNs(double seconds, std::size_t bytes) const {
  return rig::NsFromSeconds(seconds +
                            2.0 * double(dut_link::EncodedFrameBytes(bytes)) * lines_.byte_time_s);
}

namespace {

// The line closed or failed (LinkedDut names the emulator's exit instead when it died).
rig::Error LineLost(const LineReceived& received) {
  if (received.status == LineReceiveStatus::kClosed) {
    return rig::MakeError(rig::ErrorCode::kLinkClosed,
                          "the dut's serial line closed: " + received.error);
  }
  return rig::MakeError(rig::ErrorCode::kIo, "the dut's serial line failed: " + received.error);
}

}  // namespace

rig::Result<void> SerialDutLink::Exchange(
    const rig::Clock& clock, const proto::LinkMessage& message, std::int64_t interval_ns,
    std::int64_t deadline_ns, const char* waiting_for,
    const std::function<rig::Result<bool>(const proto::LinkMessage&)>& accept) {
  std::int64_t resend_ns = clock.NowNs();
  while (true) {
    const std::int64_t now_ns = clock.NowNs();
    if (now_ns >= deadline_ns) {
      if (auto exit = PeerExit()) return rig::MakeError(*exit);
      return rig::MakeError(rig::ErrorCode::kTimeout,
                            "the dut did not answer the " + std::string(waiting_for) + " within " +
                                rig::SecondsText(options_.start_timeout_s) + " on " +
                                lines_.link->name());
    }
    if (now_ns >= resend_ns) {
      // Each hello opens a session: lead with a delimiter to end any frame the DUT half holds.
      if (auto sent = link_->Send(message, kLockstepWriteTimeoutMs, /*flush_first=*/true); !sent) {
        return sent.error();
      }
      (message.has_hello() ? hellos_sent_ : configs_sent_) += 1;
      resend_ns = now_ns + interval_ns + RetryNs(0, message.ByteSizeLong());
    }
    const LineReceived received =
        link_->Receive(MillisecondsUntil(now_ns, std::min(resend_ns, deadline_ns)));
    if (received.status == LineReceiveStatus::kTimeout) continue;
    if (received.status != LineReceiveStatus::kMessage) return LineLost(received);
    auto taken = accept(received.message);
    if (!taken) return taken.error();
    if (taken.value()) return {};
    ++unexpected_messages_;
  }
}

rig::Result<void> SerialDutLink::Handshake(const rig::Clock& clock) {
  const std::int64_t deadline_ns = clock.NowNs() + rig::NsFromSeconds(options_.start_timeout_s);
  proto::LinkMessage hello;
  hello.mutable_hello()->set_role(proto::Hello::RUNNER);
  hello.mutable_hello()->set_name("hilrig " + std::to_string(::getpid()));
  sequencer_.Stamp(hello, 0);
  const auto refused = [](const proto::Bye& bye, const char* what) {
    return rig::MakeError("the dut refused the " + std::string(what) + ": " + bye.reason());
  };
  auto greeted = Exchange(
      clock, hello, rig::NsFromSeconds(options_.hello_interval_s), deadline_ns, "hello",
      [&](const proto::LinkMessage& message) -> rig::Result<bool> {
        if (message.has_bye()) return refused(message.bye(), "link");
        if (!message.has_hello() || message.hello().role() != proto::Hello::DUT) return false;
        const std::uint32_t version = message.hello().header().protocol_version();
        if (version != kHilLinkProtocolVersion) {
          return LinkProtocolError(LinkErrorKind::kBadVersion,
                                   "the dut speaks HIL link protocol version " +
                                       std::to_string(version) + ", the runner version " +
                                       std::to_string(kHilLinkProtocolVersion));
        }
        if (lines_.link_token && !ProvesLinkToken(*lines_.link_token, message.hello().token())) {
          return rig::MakeError("the dut's hello does not carry this run's link token (" +
                                std::string(message.hello().token().empty() ? "none" : "another") +
                                "): a DUT that dials the rig proves itself with the token");
        }
        dut_name_ = message.hello().name();
        return true;
      });
  if (!greeted) return greeted.error();
  proto::LinkMessage config;
  *config.mutable_config() = ToDutConfig(firmware_, control_period_s_);
  sequencer_.Stamp(config, 0);
  return Exchange(clock, config, rig::NsFromSeconds(options_.config_retry_s), deadline_ns,
                  "firmware configuration",
                  [&](const proto::LinkMessage& message) -> rig::Result<bool> {
                    if (message.has_bye()) return refused(message.bye(), "firmware configuration");
                    if (!message.has_target_info()) return false;
                    target_info_ = message.target_info();
                    return true;
                  });
}

std::optional<std::string> SerialDutLink::PeerExit() {
  if (!lines_.emulator) return std::nullopt;
  auto exit = lines_.emulator->PollExit();
  if (!exit) return std::nullopt;
  return "the dut's emulator " + *exit;
}

void SerialDutLink::Close(bool goodbye) {
  if (link_ && goodbye) {
    proto::LinkMessage bye;
    bye.mutable_bye()->set_reason("run ended");
    sequencer_.Stamp(bye, 0);
    (void)link_->Send(bye, kByeTimeoutMs);
  }
  if (lines_.emulator) lines_.emulator->Terminate(kEmulatorGraceMs);
}

rig::Result<void> SerialDutLink::Input(const DutInput& input, bool, std::int64_t) {
  // Every input rides in the next step, real time too: the line carries one message per tick.
  pending_inputs_.push_back(input);
  return {};
}

void SerialDutLink::AddInput(const DutInput& input, std::int64_t now_ns, proto::SerialStep& step) {
  proto::SerialInput* out = step.add_inputs();
  if (const auto* imu = std::get_if<ImuMessage>(&input)) {
    proto::SerialImu* serial = out->mutable_imu();
    const Eigen::Vector3d& g = imu->gyro_rad_s;
    const Eigen::Vector3d& a = imu->accel_m_s2;
    SetFloats(serial->mutable_gyro_accel(), {g.x(), g.y(), g.z(), a.x(), a.y(), a.z()});
    if (imu->stamp.time_ns != now_ns) serial->set_time_offset_ns(imu->stamp.time_ns - now_ns);
  } else if (const auto* vio = std::get_if<VioMessage>(&input)) {
    proto::SerialVio* serial = out->mutable_vio();
    if (vio->capture_time_ns != now_ns)
      serial->set_capture_offset_ns(vio->capture_time_ns - now_ns);
    SetVector(serial->mutable_position_m(), vio->position_m);
    const Eigen::Quaterniond& q = vio->orientation;
    SetFloats(serial->mutable_orientation_wxyz(), {q.w(), q.x(), q.y(), q.z()});
  } else if (const auto* setpoint = std::get_if<SetpointMessage>(&input)) {
    proto::SerialSetpoint full = FullSetpoint(*setpoint);
    *out->mutable_setpoint() = ChangedFields(full, last_setpoint_);
    last_setpoint_ = std::move(full);
  }
}

rig::Result<std::uint32_t> SerialDutLink::ForwardToCan(
    const std::vector<rig::TimedCanFrame>& frames) {
  for (const rig::TimedCanFrame& timed : frames) {
    if (auto sent = lines_.can->Send(timed.frame, timed.time_ns); !sent) {
      return rig::MakeError(sent.error().code, "forwarding a CAN frame to the dut on " +
                                                   lines_.can_uri + ": " + sent.error().message);
    }
    ++can_frames_forwarded_;
  }
  return 0;
}

rig::Result<std::uint32_t> SerialDutLink::ForwardFrames(
    const std::vector<rig::TimedCanFrame>& frames, int timeout_ms) {
  if (lines_.can) return ForwardToCan(frames);
  bridge_bytes_.clear();
  std::array<std::uint8_t, tactile_bus::kUartMaxFrameBytes> encoded;
  for (const rig::TimedCanFrame& timed : frames) {
    const std::optional<tactile_bus::NodeFrame> node = NodeFrameOf(timed);
    const std::size_t size =
        node && lines_.bridge ? tactile_bus::EncodeUartFrame(*node, encoded) : 0;
    if (size == 0) {
      ++bridge_frames_dropped_;
      continue;
    }
    bridge_bytes_.insert(bridge_bytes_.end(), encoded.begin(), encoded.begin() + size);
    ++bridge_frames_;
  }
  if (bridge_bytes_.empty()) return 0;
  if (auto written = lines_.bridge->WriteAll(bridge_bytes_, timeout_ms); !written) {
    return rig::MakeError(written.error().code,
                          "the sensor bridge line: " + written.error().message);
  }
  bridge_bytes_sent_ += bridge_bytes_.size();
  return static_cast<std::uint32_t>(bridge_bytes_.size());
}

rig::Result<void> SerialDutLink::SendLine(const proto::LinkMessage& message, int timeout_ms,
                                          bool flush_first) {
  if (auto sent = link_->Send(message, timeout_ms, flush_first); !sent) {
    return rig::MakeError(sent.error().code, "the dut's serial line: " + sent.error().message);
  }
  return {};
}

rig::Result<void> SerialDutLink::Request(const LinkRequest& request) {
  step_.Clear();
  proto::SerialStep* step = step_.mutable_serial_step();
  step->set_tick(request.tick);
  const std::int64_t offset_ns =
      request.now_ns - static_cast<std::int64_t>(request.tick) * period_ns_;
  if (offset_ns != 0) step->set_now_offset_ns(offset_ns);
  for (const DutInput& input : pending_inputs_) AddInput(input, request.now_ns, *step);
  pending_inputs_.clear();
  // A real-time plant never waits for the line: a DUT that stops reading fails the run instead.
  const int timeout_ms = request.realtime ? 0 : kLockstepWriteTimeoutMs;
  auto bridge = ForwardFrames(*request.frames, timeout_ms);
  if (!bridge) return bridge.error();
  step->set_bridge_bytes(bridge.value());
  step->set_realtime(request.realtime);
  // The DUT steps once the step and its bridge bytes are in: the longer of the two lines'
  // transfers.
  retry_ns_ =
      RetryNs(options_.step_retry_s, std::max<std::size_t>(step_.ByteSizeLong(), bridge.value()));
  if (auto sent = SendLine(step_, timeout_ms, /*flush_first=*/false); !sent) return sent;
  ++steps_sent_;
  return {};
}

rig::Result<void> SerialDutLink::Resend() {
  // A repeat leads with a delimiter: whatever half frame a lost byte left at the DUT ends.
  if (auto sent = SendLine(step_, kLockstepWriteTimeoutMs, /*flush_first=*/true); !sent) {
    return sent;
  }
  ++step_retries_;
  return {};
}

DutLinkEvent SerialDutLink::Receive(int timeout_ms) {
  LineReceived received = link_->Receive(timeout_ms);
  if (received.status == LineReceiveStatus::kTimeout) return {};
  if (received.status != LineReceiveStatus::kMessage) {
    return {DutLinkEventKind::kClosed, 0, LineLost(received)};
  }
  const proto::LinkMessage& message = received.message;
  if (message.has_bye()) {
    return {DutLinkEventKind::kFailed, 0,
            rig::MakeError("the dut ended the link: " + message.bye().reason())};
  }
  if (!message.has_serial_command()) {
    ++unexpected_messages_;
    return {DutLinkEventKind::kIgnored, 0, std::nullopt};
  }
  received_ = std::move(received.message);
  return {DutLinkEventKind::kAnswer, received_.serial_command().answers_tick(), std::nullopt};
}

rig::Result<ActuatorMessage> SerialDutLink::TakeAnswer(std::int64_t arrival_wall_ns) {
  const proto::SerialCommand& command = received_.serial_command();
  auto actuator = ActuatorFrom(command, arrival_wall_ns);
  if (!actuator) {
    return LinkProtocolError(LinkErrorKind::kMalformed,
                             "the dut sent a bad command: " + actuator.error().message);
  }
  if (command.has_counters()) dut_counters_ = command.counters();
  if (command.work_cycles() > 0) work_cycles_.Add(command.work_cycles());
  return actuator;
}

std::string SerialDutLink::timeout_detail() const {
  return " (" + std::to_string(step_retries_) + " step retries so far)";
}

std::string SerialDutLink::description() const {
  if (!link_) return "a dut on a serial line (not started)";
  std::string text = "a dut on a serial line: " + lines_.description;
  if (target_info_) text += ", target " + target_info_->board();
  if (!dut_name_.empty()) text += " (" + dut_name_ + ")";
  text += lines_.can      ? ", CAN frames over " + lines_.can_uri
          : lines_.bridge ? ", sensor bridge on " + lines_.bridge->name()
                          : ", no sensor bridge";
  return text;
}

std::vector<rig::Metric> SerialDutLink::metrics(bool) const {
  if (!link_) return {};
  const auto d = [](std::uint64_t value) { return static_cast<double>(value); };
  std::vector<rig::Metric> metrics = LineLinkMetrics(link_->counters(), "line_");
  for (const auto& [name, value] : {std::pair{"line_hellos_sent", hellos_sent_},
                                    {"line_configs_sent", configs_sent_},
                                    {"line_steps_sent", steps_sent_},
                                    {"line_step_retries", step_retries_},
                                    {"line_unexpected_messages", unexpected_messages_},
                                    {"bridge_frames_sent", bridge_frames_},
                                    {"bridge_bytes_sent", bridge_bytes_sent_},
                                    {"bridge_frames_dropped", bridge_frames_dropped_}}) {
    metrics.push_back(rig::CountMetric(name, value));
  }
  if (lines_.can)
    metrics.push_back(rig::CountMetric("link_can_frames_forwarded", can_frames_forwarded_));
  const proto::SerialDutCounters& dut = dut_counters_;
  for (const auto& [name, value] : {std::pair{"dut_line_frames_received", dut.frames_received()},
                                    {"dut_line_bad_checksum", dut.frames_bad_checksum()},
                                    {"dut_line_malformed", dut.frames_malformed()},
                                    {"dut_line_oversize", dut.frames_oversize()},
                                    {"dut_steps_repeated", dut.steps_repeated()},
                                    {"dut_steps_skipped", dut.steps_skipped()},
                                    {"dut_bridge_frames", dut.bridge_frames()},
                                    {"dut_bridge_bad_frames", dut.bridge_bad_frames()},
                                    {"dut_bridge_bytes_missing", dut.bridge_bytes_missing()},
                                    {"dut_uart_overruns", dut.uart_overruns()},
                                    {"dut_rx_ring_drops", dut.rx_ring_drops()}}) {
    metrics.push_back(rig::CountMetric(name, value));
  }
  if (const std::optional<TargetSummary> target = this->target()) {
    using rig::Unit;
    metrics.push_back({"target_work_steps", d(target->steps_measured), Unit::kCount});
    metrics.push_back({"target_work_p50_cycles", d(target->work_p50_cycles), Unit::kCycles});
    metrics.push_back({"target_work_p99_cycles", d(target->work_p99_cycles), Unit::kCycles});
    metrics.push_back({"target_work_max_cycles", d(target->work_max_cycles), Unit::kCycles});
    metrics.push_back({"target_core_clock_hz", d(target->core_clock_hz), Unit::kHertz});
    metrics.push_back({"target_flash_used_bytes", d(target->flash_used_bytes), Unit::kBytes});
    metrics.push_back({"target_ram_used_bytes", d(target->ram_used_bytes), Unit::kBytes});
    metrics.push_back({"target_stack_bytes", d(target->stack_bytes), Unit::kBytes});
  }
  return metrics;
}

std::uint64_t SerialDutLink::sensor_bytes_missing() const {
  return dut_counters_.bridge_bytes_missing();
}

std::optional<TargetSummary> SerialDutLink::target() const {
  if (!target_info_) return std::nullopt;
  TargetSummary target;
  target.board = target_info_->board();
  target.core_clock_hz = target_info_->core_clock_hz();
  target.flash_used_bytes = target_info_->flash_used_bytes();
  target.ram_used_bytes = target_info_->ram_used_bytes();
  target.stack_bytes = target_info_->stack_bytes();
  target.steps_measured = work_cycles_.count();
  target.work_p50_cycles = work_cycles_.Quantile(0.5);
  target.work_p99_cycles = work_cycles_.Quantile(0.99);
  target.work_max_cycles = work_cycles_.max();
  target.emulated_core = options_.emulated_core;
  return target;
}

}  // namespace hilrig::host
