#include "host/dut/process_dut.h"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "host/dut/process_dut_launch.h"
#include "host/link/dut_config_codec.h"
#include "rig/number_text.h"
#include "rig/udp_bus.h"

namespace hilrig::host {
namespace {

constexpr int kLockstepSendTimeoutMs = 1000;
// Per stream, and for requests: 16 s of a 1 kHz stream, far past any watchdog worth setting.
constexpr std::size_t kMaxPending = std::size_t{1} << 14;
// A closed link usually means a dead process whose exit status follows within microseconds; a
// poll waits this much wall time for it before it names the closed link instead.
constexpr std::int64_t kLinkClosedGraceNs = 200'000'000;
// Bounds one poll's work on a DUT that floods the link.
constexpr int kMaxEventsPerPoll = 4096;

rig::Result<std::string> DutEmuPath(const ProcessDutOptions& options) {
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

std::string ListenEndpoint(const ProcessDutOptions& options) {
  return options.listen_address + ":" + std::to_string(options.listen_port);
}

rig::Result<rig::CanBusUri> ParseDutCanBusUri(const std::string& uri) {
  auto parsed = rig::ParseCanBusUri(uri);
  if (!parsed) return parsed.error();
  const auto refused = [&uri](const std::string& why) {
    return rig::MakeError("CAN bus \"" + uri + "\": " + why);
  };
  switch (parsed.value().scheme) {
    case rig::CanBusUri::Scheme::kSocketCan:
      return parsed;
    case rig::CanBusUri::Scheme::kEmulated:
      return refused(
          "an emulated bus lives inside one process, the dut process cannot reach it; "
          "a run's dut bus is socketcan:IFACE");
    case rig::CanBusUri::Scheme::kUdp:
      return refused(
          "the rig chooses the run's own UDP bus to the dut process itself; "
          "a run's dut bus is socketcan:IFACE");
    case rig::CanBusUri::Scheme::kGsUsb:
      return refused(
          "one process claims a gs_usb adapter over libusb, so the runner and the dut process "
          "cannot share it; bring it up under the kernel's gs_usb driver and use socketcan:IFACE");
  }
  return refused("unknown scheme");
}

rig::Result<void> ValidateProcessDutOptions(const ProcessDutOptions& options) {
  const auto bad_timeout = [](double seconds) {
    return !std::isfinite(seconds) || seconds <= 0 || seconds > 3600;
  };
  if (options.pacing == DutPacing::kRealtime && options.wall_clock == nullptr) {
    return rig::MakeError(
        "a real-time dut process needs a wall clock (ProcessDutOptions::wall_clock)");
  }
  if (bad_timeout(options.answer_timeout_s)) {
    return rig::MakeError("dut answer timeout " + rig::NumberText(options.answer_timeout_s) +
                          " s: must be positive, finite and at most an hour");
  }
  if (bad_timeout(options.start_timeout_s)) {
    return rig::MakeError("dut start timeout " + rig::NumberText(options.start_timeout_s) +
                          " s: must be positive, finite and at most an hour");
  }
  if (options.listen_address.empty()) return rig::MakeError("empty link listen address");
  if (options.transport == DutLinkTransport::kSharedMemory &&
      options.listen_address != ProcessDutOptions{}.listen_address) {
    return rig::MakeError(
        "link listen address " + options.listen_address +
        ": a listen address is for the TCP link, the shared-memory link has none");
  }
  if (options.listen) {
    if (options.transport != DutLinkTransport::kTcp) {
      return rig::MakeError("a DUT that dials in does so over the TCP link");
    }
    if (options.listen_port == 0 || options.listen_port == 65535) {
      return rig::MakeError("listen port " + std::to_string(options.listen_port) +
                            ": must be 1 to 65534 (the CAN bus takes the next one)");
    }
    if (options.token_file.empty()) return rig::MakeError("a listening DUT needs a token file");
  }
  if (!options.can_uri.empty()) {
    if (auto uri = ParseDutCanBusUri(options.can_uri); !uri) return uri.error();
  }
  return {};
}

ProcessDut::ProcessDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> runner_bus,
                       double control_period_s, const ProcessDutOptions& options)
    : firmware_(firmware),
      control_period_s_(control_period_s),
      runner_bus_(std::move(runner_bus)),
      options_(options),
      ledger_(std::llround(options.answer_timeout_s * 1e9)) {
  frames_.reserve(64);
  if (realtime() && options_.wall_clock != nullptr) latencies_ = std::make_unique<Latencies>();
}

rig::Result<std::unique_ptr<ProcessDut>> ProcessDut::Launch(const DutFirmware& firmware,
                                                            std::unique_ptr<rig::CanBus> runner_bus,
                                                            double control_period_s,
                                                            const ProcessDutOptions& options) {
  auto dut =
      std::make_unique<ProcessDut>(firmware, std::move(runner_bus), control_period_s, options);
  if (auto started = dut->Start(); !started) return started.error();
  return dut;
}

rig::Result<void> ProcessDut::Start() {
  if (started_) return rig::MakeError("the dut process was started already");
  if (auto valid = ValidateProcessDutOptions(options_); !valid) return valid.error();
  std::string path;
  if (!options_.listen) {
    auto found = DutEmuPath(options_);
    if (!found) return found.error();
    path = std::move(found).value();
  }
  auto launched = LaunchDut(path, options_);
  if (!launched) return launched.error();
  std::unique_ptr<LinkConnection>& link = launched.value().link;

  // Only the proven DUT hears from the runner, the firmware included.
  proto::LinkMessage hello;
  hello.mutable_hello()->set_role(proto::Hello::RUNNER);
  hello.mutable_hello()->set_name("hilrig " + std::to_string(::getpid()));
  sequencer_.Stamp(hello, 0);
  proto::LinkMessage config;
  *config.mutable_config() = ToDutConfig(firmware_, control_period_s_);
  sequencer_.Stamp(config, 0);
  for (const proto::LinkMessage* message : {&hello, &config}) {
    if (auto sent = link->Send(*message); !sent) return sent.error();
  }
  started_ = true;
  child_ = std::move(launched.value().child);
  link_ = std::move(link);
  forward_bus_ = std::move(launched.value().forward_bus);
  peers_refused_ = launched.value().peers_refused;
  peers_refused_summary_ = launched.value().peers_refused_summary;
  return {};
}

void ProcessDut::Stop() {
  if (stopped_ || !started_) return;
  stopped_ = true;
  if (!failure_) {
    proto::LinkMessage bye;
    bye.mutable_bye()->set_reason("run ended");
    sequencer_.Stamp(bye, 0);
    (void)link_->Send(bye, 100);
  }
  if (child_) child_->Terminate(1000);
}

ProcessDut::~ProcessDut() { Stop(); }

std::string ProcessDut::description() const {
  const std::string what = options_.listen ? "a DUT that dialled " + ListenEndpoint(options_)
                           : options_.program.empty() ? "dut_fw in a dut_emu process"
                                                      : "the program " + options_.program;
  if (!started_) return what + " (not started)";
  const std::string process = child_ ? " (pid " + std::to_string(child_->pid()) + ")" : "";
  return what + process + " over the " +
         (options_.transport == DutLinkTransport::kSharedMemory ? "shared-memory" : "TCP") +
         " HIL link, " + (realtime() ? "real time" : "lockstep") +
         (options_.can_uri.empty() ? "" : ", CAN frames over " + options_.can_uri) +
         (peers_refused_summary_.empty() ? "" : "; " + peers_refused_summary_);
}

std::vector<rig::Metric> ProcessDut::link_metrics() const {
  if (!link_) return {};
  std::vector<rig::Metric> metrics = LinkCounterMetrics(link_->counters(), "link_rx_");
  metrics.emplace_back("link_tx_messages", static_cast<double>(link_->frames_sent()));
  metrics.emplace_back("link_commands_received", static_cast<double>(commands_received_));
  metrics.emplace_back("link_can_frames_forwarded", static_cast<double>(can_frames_forwarded_));
  metrics.emplace_back("link_watchdog_timeouts", static_cast<double>(ledger_.watchdog_timeouts()));
  metrics.emplace_back("link_peers_refused", static_cast<double>(peers_refused_));
  metrics.emplace_back("dut_can_frames_dropped_foreign",
                       static_cast<double>(dut_frames_dropped_foreign_));
  metrics.emplace_back("dut_can_frames_dropped_malformed",
                       static_cast<double>(dut_frames_dropped_malformed_));
  // The runner's end of the DUT's CAN bus drops what the DUT's end would: say so too.
  if (forward_bus_) {
    const rig::BusCounters bus = forward_bus_->counters();
    metrics.emplace_back("link_can_frames_dropped_malformed",
                         static_cast<double>(bus.frames_dropped_malformed));
    metrics.emplace_back("link_can_frames_dropped_foreign",
                         static_cast<double>(bus.frames_dropped_foreign));
  }
  if (!realtime()) return metrics;  // the rest measure real-time pacing, which lockstep has none of
  const auto d = [](std::uint64_t value) { return static_cast<double>(value); };
  metrics.emplace_back("link_commands_superseded", d(commands_superseded_));
  metrics.emplace_back("link_requests_skipped", d(ledger_.requests_skipped()));
  // Answers to a tick never asked for, or to one answered already: either fails the run.
  metrics.emplace_back("link_unrequested_answers",
                       d(ledger_.unrequested_answers() + ledger_.stale_answers()));
  metrics.emplace_back("link_latency_samples_dropped", d(latency_samples_dropped_));
  metrics.emplace_back("dut_can_frame_waits_expired", d(dut_frame_waits_expired_));
  return metrics;
}

std::vector<StreamLatency> ProcessDut::response_latencies() const {
  if (!latencies_) return {};
  std::vector<StreamLatency> latencies;
  for (std::size_t index = 0; index < kDutInputStreams; ++index) {
    latencies.push_back({DutInputStream(index), latencies_->inputs[index].latency.Summary()});
  }
  latencies.push_back({"can", latencies_->can.latency.Summary()});
  latencies.push_back({"command", latencies_->command.Summary()});
  return latencies;
}

rig::Error ProcessDut::Failed(std::string message) {
  return Failed(rig::MakeError(std::move(message)));
}

rig::Error ProcessDut::Failed(rig::Error error) {
  if (!failure_) failure_ = std::move(error);
  return *failure_;
}

std::optional<std::string> ProcessDut::ChildExit() {
  return child_ ? child_->PollExit() : std::nullopt;
}

std::string ProcessDut::ProcessGone() {
  if (!child_) return "the DUT closed the link";
  // The link closes as the process dies; its exit status follows within moments.
  const timespec nap{0, 5'000'000};
  for (int waited_ms = 0; waited_ms < 200; waited_ms += 5) {
    if (auto exit = ChildExit()) return "dut process " + *exit;
    ::nanosleep(&nap, nullptr);
  }
  return "dut closed the link (process still running)";
}

rig::Result<void> ProcessDut::CheckRunning() {
  if (failure_) return *failure_;
  if (!link_ || stopped_) return Failed("the dut process is not running (not started, or stopped)");
  return {};
}

void ProcessDut::Forward(const proto::LinkMessage& message, bool input) {
  if (!CheckRunning()) return;
  if (input && !realtime()) {
    // Nothing waits for an input alone: it goes out with the tick's request, in one write.
    if (auto queued = link_->Queue(message); !queued) {
      (void)Failed("link send failed: " + queued.error().message);
    }
    return;
  }
  // A real-time plant never waits for the socket: a DUT that stops reading fails the run instead.
  const int timeout_ms = realtime() ? 0 : kLockstepSendTimeoutMs;
  if (auto sent = link_->Send(message, timeout_ms); !sent) {
    if (realtime() && link_->closed() && !ChildExit()) {
      // Most likely a process still dying: the next polls name it, or the closed link.
      if (!link_closed_wall_ns_) link_closed_wall_ns_ = options_.wall_clock->NowNs();
      return;
    }
    (void)Failed(ChildExit() ? "dut process " + *ChildExit()
                             : "link send failed: " + sent.error().message);
  }
}

void ProcessDut::LogSend(SendLog& log, std::uint64_t key, std::int64_t wall_ns) {
  if (log.pending.size() >= kMaxPending) {
    log.pending.pop_front();
    ++latency_samples_dropped_;
  }
  log.pending.push_back({key, wall_ns});
}

void ProcessDut::Cover(SendLog& log, std::uint64_t up_to_key, std::int64_t arrival_wall_ns) {
  while (!log.pending.empty() && log.pending.front().key <= up_to_key) {
    log.latency.Add(arrival_wall_ns - log.pending.front().wall_ns);
    log.pending.pop_front();
  }
}

void ProcessDut::Send(const DutInput& input) {
  counters_.Count(input);
  if (latencies_) {
    LogSend(latencies_->inputs[input.index()], StampOf(input).sequence,
            options_.wall_clock->NowNs());
  }
  Forward(ToLink(input), /*input=*/true);
}

rig::Result<void> ProcessDut::SendStepRequest(std::uint64_t tick, std::int64_t now_ns,
                                              bool realtime) {
  if (auto running = CheckRunning(); !running) return running.error();
  if (auto next = ledger_.CheckNext(tick); !next) return Failed(next.error());
  const std::int64_t wall_ns = latencies_ ? options_.wall_clock->NowNs() : 0;
  frames_.clear();
  runner_bus_->Receive(now_ns, frames_);
  proto::LinkMessage request;
  proto::StepRequest* step = request.mutable_step();
  step->set_tick(tick);
  step->set_now_ns(now_ns);
  step->set_can_frames_sent(frames_.size());
  step->set_realtime(realtime);
  for (const rig::TimedCanFrame& timed : frames_) {
    if (auto handed = HandOver(timed, *step); !handed) return handed.error();
    step->add_can_frame_time_ns(timed.time_ns);
    ++can_frames_forwarded_;
    if (latencies_) LogSend(latencies_->can, can_frames_forwarded_, wall_ns);
  }
  counters_.can_frames_received += frames_.size();
  sequencer_.Stamp(request, now_ns);
  Forward(request);
  if (failure_) return *failure_;
  ledger_.Add(tick, wall_ns);
  return {};
}

rig::Result<void> ProcessDut::HandOver(const rig::TimedCanFrame& timed, proto::StepRequest& step) {
  // The sender time in the datagram is the arrival time too; the DUT takes it from the request.
  if (!forward_bus_) {
    if (auto valid = rig::ValidateFrame(timed.frame); !valid) {
      return Failed("a CAN frame for the dut: " + valid.error().message);
    }
    std::array<std::uint8_t, rig::kUdpCanMaxDatagramBytes> datagram;
    const std::size_t size = rig::EncodeUdpCanDatagram(timed.frame, timed.time_ns, datagram);
    step.add_can_frame(datagram.data(), size);
    return {};
  }
  if (auto sent = forward_bus_->Send(timed.frame, timed.time_ns); !sent) {
    return Failed("forwarding a CAN frame to the dut: " + sent.error().message);
  }
  return {};
}

rig::Result<ActuatorMessage> ProcessDut::Step(std::uint64_t tick, std::int64_t now_ns) {
  if (auto sent = SendStepRequest(tick, now_ns, /*realtime=*/false); !sent) return sent.error();
  return AwaitCommand(tick);
}

void ProcessDut::RequestStep(std::uint64_t tick, std::int64_t now_ns) {
  if (failure_) return;
  if (!realtime()) {
    (void)Failed("a real-time step request to a lockstep dut process (ProcessDutOptions::pacing)");
    return;
  }
  (void)SendStepRequest(tick, now_ns, /*realtime=*/true);  // a failure sticks for the next poll
}

rig::Result<std::optional<ActuatorMessage>> ProcessDut::PollCommand() {
  if (auto running = CheckRunning(); !running) return running.error();
  if (!realtime()) {
    return Failed("a real-time poll of a lockstep dut process (ProcessDutOptions::pacing)");
  }
  const std::int64_t now_ns = options_.wall_clock->NowNs();
  std::optional<ActuatorMessage> newest;
  for (int events = 0; events < kMaxEventsPerPoll && !link_closed_wall_ns_; ++events) {
    const LinkReceived received = link_->Poll();
    if (received.status == LinkReceiveStatus::kTimeout) break;
    if (received.status == LinkReceiveStatus::kClosed) {
      link_closed_wall_ns_ = now_ns;
      break;
    }
    auto command = TakeCommand(received, now_ns);
    if (!command) return command.error();
    if (newest) ++commands_superseded_;
    newest = std::move(command).value();
  }
  if (auto alive = CheckAlive(now_ns); !alive) return alive.error();
  return newest;
}

rig::Result<void> ProcessDut::CheckAlive(std::int64_t now_wall_ns) {
  if (auto exit = ChildExit()) return Failed("dut process " + *exit);
  if (link_closed_wall_ns_) {
    // Nothing can answer any more; name the closed link unless the exit status turns up in time.
    if (now_wall_ns - *link_closed_wall_ns_ < kLinkClosedGraceNs) return {};
    return Failed("link closed (the dut process is still running)");
  }
  if (auto tick = ledger_.Overdue(now_wall_ns)) {
    return Failed(OverdueError(*tick, options_.answer_timeout_s));
  }
  return {};
}

rig::Result<ActuatorMessage> ProcessDut::AwaitCommand(std::uint64_t tick) {
  const rig::Clock& clock = options_.wall_clock != nullptr ? *options_.wall_clock : own_wall_clock_;
  constexpr std::int64_t kNsPerMs = 1'000'000;
  const std::int64_t deadline_ns =
      clock.NowNs() + std::int64_t{CeilMilliseconds(options_.answer_timeout_s)} * kNsPerMs;
  while (true) {
    const std::int64_t left_ms = (deadline_ns - clock.NowNs()) / kNsPerMs;
    if (left_ms <= 0) break;
    LinkReceived received =
        link_->Receive(static_cast<int>(std::min<std::int64_t>(left_ms, kPollSliceMs)));
    switch (received.status) {
      case LinkReceiveStatus::kTimeout:
        if (auto exit = ChildExit()) return Failed("dut process " + *exit);
        continue;
      case LinkReceiveStatus::kClosed:
        return Failed(ProcessGone());
      default:
        return TakeCommand(received, latencies_ ? options_.wall_clock->NowNs() : 0);
    }
  }
  ledger_.CountTimeout();
  if (auto exit = ChildExit()) return Failed("dut process " + *exit);
  return Failed(rig::MakeError(rig::ErrorCode::kTimeout,
                               "dut did not answer tick " + std::to_string(tick) + " within " +
                                   rig::SecondsText(options_.answer_timeout_s)));
}

rig::Result<ActuatorMessage> ProcessDut::TakeCommand(const LinkReceived& received,
                                                     std::int64_t arrival_wall_ns) {
  if (received.status == LinkReceiveStatus::kLinkError) {
    return Failed(LinkReceiveError(received, "dut sent a bad message (" + received.error + ")"));
  }
  if (received.status != LinkReceiveStatus::kMessage) {
    return Failed(LinkReceiveError(received, "link to the dut failed: " + received.error));
  }
  const proto::LinkMessage& message = received.message;
  if (message.has_bye()) {
    return Failed("dut ended the link: " + message.bye().reason());
  }
  if (!message.has_command()) {
    return Failed(
        "dut sent an unexpected " +
        proto::LinkMessage::descriptor()->FindFieldByNumber(message.payload_case())->name() +
        " message instead of the command for tick " +
        std::to_string(ledger_.last_requested().value_or(0)));
  }
  if (auto matched = MatchRequest(message.command().answers_sequence(), arrival_wall_ns);
      !matched) {
    return matched.error();
  }
  auto command = FromLink(message.command());
  if (!command) return Failed("dut sent a bad command: " + command.error().message);
  RecordCoverage(message.command(), arrival_wall_ns);
  ++commands_received_;
  return command;
}

rig::Result<void> ProcessDut::MatchRequest(std::uint64_t answers_tick,
                                           std::int64_t arrival_wall_ns) {
  const std::optional<std::uint64_t> last_answered = ledger_.last_answered();
  const RequestLedger::Answer answer = ledger_.Take(answers_tick, arrival_wall_ns);
  switch (answer.outcome) {
    case RequestLedger::Outcome::kAnswers:
      if (latencies_) latencies_->command.Add(answer.waited_ns);
      return {};
    case RequestLedger::Outcome::kStale:
      return Failed("dut answered tick " + std::to_string(answers_tick) + " after tick " +
                    std::to_string(last_answered.value_or(0)) + " (answers went backwards)");
    case RequestLedger::Outcome::kNeverRequested:
      break;
  }
  const std::optional<std::uint64_t> last_requested = ledger_.last_requested();
  return Failed("dut answered tick " + std::to_string(answers_tick) +
                ", which was never requested (last request: tick " +
                (last_requested ? std::to_string(*last_requested) : "none") + ")");
}

void ProcessDut::RecordCoverage(const proto::ActuatorCommand& command,
                                std::int64_t arrival_wall_ns) {
  dut_frame_waits_expired_ = command.can_frame_waits_expired();
  dut_frames_dropped_foreign_ = command.can_frames_dropped_foreign();
  dut_frames_dropped_malformed_ = command.can_frames_dropped_malformed();
  if (!latencies_) return;
  for (std::size_t index = 0; index < kDutInputStreams; ++index) {
    if (auto taken = LastTakenSequence(command, index)) {
      Cover(latencies_->inputs[index], *taken, arrival_wall_ns);
    }
  }
  Cover(latencies_->can, command.can_frames_consumed(), arrival_wall_ns);
}

}  // namespace hilrig::host
