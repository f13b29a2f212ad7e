#include "host/linked_dut/process_dut_link.h"

#include <unistd.h>

#include <filesystem>

#include "host/link/dut_config_codec.h"
#include "host/linked_dut/process_dut_launch.h"
#include "rig/udp_bus.h"

namespace hilrig::host {
namespace {

constexpr int kLockstepSendTimeoutMs = 1000;
constexpr int kByeTimeoutMs = 100;
constexpr int kTerminateGraceMs = 1000;  // dut_emu flushes its log on SIGTERM
// Per stream: 16 s of a 1 kHz stream, far past any watchdog worth setting.
constexpr std::size_t kMaxPending = std::size_t{1} << 14;

rig::Result<std::string> ProgramPath(const ProcessDutOptions& options) {
  if (!options.program.empty()) {
    // A path as it is; a bare name in the folders of PATH, as a shell finds it.
    std::string path = options.program;
    if (path.find('/') == std::string::npos) {
      auto found = FindInPath(path);
      if (!found) return rig::MakeError("no program \"" + path + "\" in PATH");
      path = std::move(found).value();
    }
    if (::access(path.c_str(), X_OK) != 0) {
      return rig::MakeError("no executable program at " + path);
    }
    return path;
  }
  std::string path = options.dut_emu_path;
  if (path.empty()) {
    auto directory = ExecutableDirectory();
    if (!directory) return directory.error();
    path = (std::filesystem::path(directory.value()) / "dut_emu").string();
  }
  if (::access(path.c_str(), X_OK) != 0) {
    return rig::MakeError("no dut_emu executable at " + path + " (build the dut_emu target)");
  }
  return path;
}

}  // namespace

ProcessDutLink::ProcessDutLink(const DutFirmware& firmware, double control_period_s,
                               const ProcessDutOptions& options)
    : firmware_(firmware),
      control_period_s_(control_period_s),
      options_(options),
      realtime_(options.pacing == DutPacing::kRealtime) {}

rig::Result<void> ProcessDutLink::Open(const rig::Clock&) {
  if (auto valid = ValidateProcessDutOptions(options_); !valid) return valid.error();
  std::string path;
  if (!options_.listen) {
    auto found = ProgramPath(options_);
    if (!found) return found.error();
    path = std::move(found).value();
  }
  auto launched = LaunchDut(path, options_);
  if (!launched) return launched.error();
  child_ = std::move(launched.value().child);
  link_ = std::move(launched.value().link);
  forward_bus_ = std::move(launched.value().forward_bus);
  peers_refused_ = launched.value().peers_refused;
  peers_refused_summary_ = launched.value().peers_refused_summary;

  // Only the proven DUT hears from the runner, the firmware included.
  proto::LinkMessage hello;
  hello.mutable_hello()->set_role(proto::Hello::RUNNER);
  hello.mutable_hello()->set_name("hilrig " + std::to_string(::getpid()));
  sequencer_.Stamp(hello, 0);
  proto::LinkMessage config;
  *config.mutable_config() = ToDutConfig(firmware_, control_period_s_);
  sequencer_.Stamp(config, 0);
  for (const proto::LinkMessage* message : {&hello, &config}) {
    if (auto sent = link_->Send(*message); !sent) return sent.error();
  }
  return {};
}

std::optional<std::string> ProcessDutLink::PeerExit() {
  if (!child_) return std::nullopt;
  auto exit = child_->PollExit();
  if (!exit) return std::nullopt;
  return "dut process " + *exit;
}

void ProcessDutLink::Close(bool goodbye) {
  if (link_ && goodbye) {
    proto::LinkMessage bye;
    bye.mutable_bye()->set_reason("run ended");
    sequencer_.Stamp(bye, 0);
    (void)link_->Send(bye, kByeTimeoutMs);
  }
  if (child_) child_->Terminate(kTerminateGraceMs);
}

rig::Result<void> ProcessDutLink::Send(const proto::LinkMessage& message, bool realtime) {
  // A real-time plant never waits for the socket: a DUT that stops reading fails the run instead.
  if (auto sent = link_->Send(message, realtime ? 0 : kLockstepSendTimeoutMs); !sent) {
    if (link_->closed()) {
      return rig::MakeError(rig::ErrorCode::kLinkClosed, "the dut closed the link");
    }
    return rig::MakeError(sent.error().code, "link send failed: " + sent.error().message);
  }
  return {};
}

rig::Result<void> ProcessDutLink::Input(const DutInput& input, bool realtime,
                                        std::int64_t sent_wall_ns) {
  if (realtime_) LogSend(input_logs_[input.index()], StampOf(input).sequence, sent_wall_ns);
  if (realtime) return Send(ToLink(input), realtime);
  // Nothing waits for an input alone: it goes out with the tick's request, in one write.
  if (auto queued = link_->Queue(ToLink(input)); !queued) {
    return rig::MakeError("link send failed: " + queued.error().message);
  }
  return {};
}

rig::Result<void> ProcessDutLink::Request(const LinkRequest& request) {
  proto::LinkMessage message;
  proto::StepRequest* step = message.mutable_step();
  step->set_tick(request.tick);
  step->set_now_ns(request.now_ns);
  step->set_can_frames_sent(request.frames->size());
  step->set_realtime(request.realtime);
  for (const rig::TimedCanFrame& timed : *request.frames) {
    if (auto handed = HandOver(timed, *step); !handed) return handed.error();
    step->add_can_frame_time_ns(timed.time_ns);
    ++can_frames_forwarded_;
    if (realtime_) LogSend(can_log_, can_frames_forwarded_, request.sent_wall_ns);
  }
  sequencer_.Stamp(message, request.now_ns);
  return Send(message, request.realtime);
}

rig::Result<void> ProcessDutLink::HandOver(const rig::TimedCanFrame& timed,
                                           proto::StepRequest& step) {
  // The sender time in the datagram is the arrival time too; the DUT takes it from the request.
  if (!forward_bus_) {
    if (auto valid = rig::ValidateFrame(timed.frame); !valid) {
      return rig::MakeError("a CAN frame for the dut: " + valid.error().message);
    }
    std::array<std::uint8_t, rig::kUdpCanMaxDatagramBytes> datagram;
    const std::size_t size = rig::EncodeUdpCanDatagram(timed.frame, timed.time_ns, datagram);
    step.add_can_frame(datagram.data(), size);
    return {};
  }
  if (auto sent = forward_bus_->Send(timed.frame, timed.time_ns); !sent) {
    return rig::MakeError("forwarding a CAN frame to the dut: " + sent.error().message);
  }
  return {};
}

DutLinkEvent ProcessDutLink::Receive(int timeout_ms) {
  LinkReceived received = link_->Receive(timeout_ms);
  switch (received.status) {
    case LinkReceiveStatus::kTimeout:
      return {};
    case LinkReceiveStatus::kClosed:
      return {DutLinkEventKind::kClosed, 0,
              rig::MakeError(rig::ErrorCode::kLinkClosed, "the dut closed the link")};
    case LinkReceiveStatus::kSocketError:
      return {DutLinkEventKind::kClosed, 0,
              LinkReceiveError(received, "link to the dut failed: " + received.error)};
    case LinkReceiveStatus::kLinkError:
      return {DutLinkEventKind::kFailed, 0,
              LinkReceiveError(received, "dut sent a bad message (" + received.error + ")")};
    case LinkReceiveStatus::kMessage:
      break;
  }
  const proto::LinkMessage& message = received.message;
  if (message.has_bye()) {
    return {DutLinkEventKind::kFailed, 0,
            rig::MakeError("dut ended the link: " + message.bye().reason())};
  }
  if (!message.has_command()) {
    return {
        DutLinkEventKind::kFailed, 0,
        rig::MakeError(
            "dut sent an unexpected " +
            proto::LinkMessage::descriptor()->FindFieldByNumber(message.payload_case())->name() +
            " message instead of a command")};
  }
  received_ = std::move(received.message);
  return {DutLinkEventKind::kAnswer, received_.command().answers_sequence(), std::nullopt};
}

rig::Result<ActuatorMessage> ProcessDutLink::TakeAnswer(std::int64_t arrival_wall_ns) {
  auto command = FromLink(received_.command());
  if (!command) return rig::MakeError("dut sent a bad command: " + command.error().message);
  RecordCoverage(received_.command(), arrival_wall_ns);
  return command;
}

void ProcessDutLink::LogSend(SendLog& log, std::uint64_t key, std::int64_t wall_ns) {
  if (log.pending.size() >= kMaxPending) {
    log.pending.pop_front();
    ++latency_samples_dropped_;
  }
  log.pending.push_back({key, wall_ns});
  log.used = true;
}

void ProcessDutLink::Cover(SendLog& log, std::uint64_t up_to_key, std::int64_t arrival_wall_ns) {
  while (!log.pending.empty() && log.pending.front().key <= up_to_key) {
    log.latency.Add(arrival_wall_ns - log.pending.front().wall_ns);
    log.pending.pop_front();
  }
}

void ProcessDutLink::RecordCoverage(const proto::ActuatorCommand& command,
                                    std::int64_t arrival_wall_ns) {
  dut_frame_waits_expired_ = command.can_frame_waits_expired();
  dut_frames_dropped_foreign_ = command.can_frames_dropped_foreign();
  dut_frames_dropped_malformed_ = command.can_frames_dropped_malformed();
  if (command.has_front_end()) front_end_ = command.front_end();
  if (!realtime_) return;
  for (std::size_t index = 0; index < kDutInputStreams; ++index) {
    if (auto taken = LastTakenSequence(command, index)) {
      Cover(input_logs_[index], *taken, arrival_wall_ns);
    }
  }
  Cover(can_log_, command.can_frames_consumed(), arrival_wall_ns);
}

std::vector<StreamLatency> ProcessDutLink::input_latencies() const {
  std::vector<StreamLatency> latencies;
  for (std::size_t index = 0; index < kDutInputStreams; ++index) {
    // A stream the DUT was never sent (the navigation sensors, for the rig's own controller) has
    // no latency to report.
    if (!input_logs_[index].used) continue;
    latencies.push_back({DutInputStream(index), input_logs_[index].latency.Summary()});
  }
  latencies.push_back({"can", can_log_.latency.Summary()});
  return latencies;
}

std::string ProcessDutLink::description() const {
  const std::string what = options_.listen ? "a DUT that dialled " + ListenEndpoint(options_)
                           : options_.program.empty() ? "dut_fw in a dut_emu process"
                                                      : "the program " + options_.program;
  if (!link_) return what + " (not started)";
  const std::string process = child_ ? " (pid " + std::to_string(child_->pid()) + ")" : "";
  return what + process + " over the " +
         (options_.transport == DutLinkTransport::kSharedMemory ? "shared-memory" : "TCP") +
         " HIL link, " + (realtime_ ? "real time" : "lockstep") +
         (options_.can_uri.empty() ? "" : ", CAN frames over " + options_.can_uri) +
         (peers_refused_summary_.empty() ? "" : "; " + peers_refused_summary_);
}

std::vector<rig::Metric> ProcessDutLink::metrics(bool realtime) const {
  if (!link_) return {};
  std::vector<rig::Metric> metrics = LinkCounterMetrics(link_->counters(), "link_rx_");
  metrics.push_back(rig::CountMetric("link_tx_messages", link_->frames_sent()));
  for (const auto& [name, value] :
       {std::pair{"link_can_frames_forwarded", can_frames_forwarded_},
        {"link_peers_refused", peers_refused_},
        {"dut_can_frames_dropped_foreign", dut_frames_dropped_foreign_},
        {"dut_can_frames_dropped_malformed", dut_frames_dropped_malformed_}}) {
    metrics.push_back(rig::CountMetric(name, value));
  }
  // The runner's end of the DUT's CAN bus drops what the DUT's end would: say so too.
  if (forward_bus_) {
    const rig::BusCounters bus = forward_bus_->counters();
    metrics.push_back(
        rig::CountMetric("link_can_frames_dropped_malformed", bus.frames_dropped_malformed));
    metrics.push_back(
        rig::CountMetric("link_can_frames_dropped_foreign", bus.frames_dropped_foreign));
  }
  if (!realtime) return metrics;  // the rest measure real-time pacing, which lockstep has none of
  metrics.push_back(rig::CountMetric("link_latency_samples_dropped", latency_samples_dropped_));
  metrics.push_back(rig::CountMetric("dut_can_frame_waits_expired", dut_frame_waits_expired_));
  return metrics;
}

}  // namespace hilrig::host
