#include "host/dut/process_dut.h"

#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "host/link/dut_config_codec.h"

namespace hilrig::host {
namespace {

constexpr int kPollSliceMs = 20;  // how often a waiting runner checks that the process lives

std::string Seconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g s", seconds);
  return text;
}

int Milliseconds(double seconds) { return static_cast<int>(std::ceil(seconds * 1000)); }

rig::Result<std::string> DutEmuPath(const ProcessDutOptions& options) {
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

// The address the child dials: the listening one, or loopback when listening on every address.
std::string DialAddress(const std::string& listen_address) {
  if (listen_address == "0.0.0.0") return "127.0.0.1";
  if (listen_address == "::") return "::1";
  return listen_address;
}

// Waits for the child to say hello on the link, watching it does not die meanwhile.
rig::Result<proto::LinkMessage> ReceiveWhileAlive(LinkConnection& link, ChildProcess& child,
                                                  int timeout_ms, const std::string& what) {
  for (int waited_ms = 0; waited_ms < timeout_ms; waited_ms += kPollSliceMs) {
    LinkReceived received = link.Receive(kPollSliceMs);
    if (received.status == LinkReceiveStatus::kMessage) return std::move(received.message);
    if (received.status != LinkReceiveStatus::kTimeout) {
      return rig::MakeError("link failed while waiting for the " + what + ": " +
                            (received.error.empty() ? "closed" : received.error));
    }
    if (auto exit = child.PollExit()) {
      return rig::MakeError("dut process " + *exit + " before its " + what);
    }
  }
  return rig::MakeError("no " + what + " from the dut process within " +
                        std::to_string(timeout_ms) + " ms");
}

rig::Result<std::unique_ptr<LinkConnection>> AcceptWhileAlive(LinkListener& listener,
                                                              ChildProcess& child, int timeout_ms) {
  for (int waited_ms = 0; waited_ms < timeout_ms; waited_ms += kPollSliceMs) {
    auto link = listener.Accept(kPollSliceMs);
    if (link) return link;
    if (auto exit = child.PollExit()) {
      return rig::MakeError("dut process " + *exit + " before connecting to the link");
    }
  }
  return rig::MakeError("the dut process did not connect to the link within " +
                        std::to_string(timeout_ms) + " ms");
}

}  // namespace

rig::Result<void> ValidateProcessDutOptions(const ProcessDutOptions& options) {
  const auto bad_timeout = [](double seconds) {
    return !std::isfinite(seconds) || seconds <= 0 || seconds > 3600;
  };
  if (bad_timeout(options.answer_timeout_s)) {
    return rig::MakeError("dut answer timeout " + std::to_string(options.answer_timeout_s) +
                          " s: must be positive, finite and at most an hour");
  }
  if (bad_timeout(options.start_timeout_s)) {
    return rig::MakeError("dut start timeout " + std::to_string(options.start_timeout_s) +
                          " s: must be positive, finite and at most an hour");
  }
  if (options.listen_address.empty()) return rig::MakeError("empty link listen address");
  return {};
}

rig::Result<std::unique_ptr<ProcessDut>> ProcessDut::Start(const DutFirmware& firmware,
                                                           std::unique_ptr<rig::CanBus> runner_bus,
                                                           double control_period_s,
                                                           const ProcessDutOptions& options) {
  if (auto valid = ValidateProcessDutOptions(options); !valid) return valid.error();
  auto path = DutEmuPath(options);
  if (!path) return path.error();
  auto listener = LinkListener::Listen(options.listen_address, 0);
  if (!listener) return listener.error();
  // Node 0 of the UDP bus is the runner's forwarder; node 1's port is freed for the child.
  auto udp = rig::OpenUdpBusGroup(2);
  if (!udp) return rig::MakeError("UDP CAN bus for the dut: " + udp.error().message);
  std::unique_ptr<rig::UdpBus> forward_bus = std::move(udp.value()[0]);
  udp.value()[1].reset();
  std::vector<std::string> argv = {
      path.value(), "--link",
      DialAddress(options.listen_address) + ":" + std::to_string(listener.value()->port()), "--can",
      "udp:" + std::to_string(forward_bus->local_port()) + ":1:2"};
  argv.insert(argv.end(), options.extra_args.begin(), options.extra_args.end());
  auto child = ChildProcess::Spawn(argv);
  if (!child) return child.error();
  const int start_ms = Milliseconds(options.start_timeout_s);
  auto link = AcceptWhileAlive(*listener.value(), child.value(), start_ms);
  if (!link) return link.error();

  LinkSequencer sequencer;
  proto::LinkMessage hello;
  hello.mutable_hello()->set_role(proto::Hello::RUNNER);
  hello.mutable_hello()->set_name("hilrig " + std::to_string(::getpid()));
  sequencer.Stamp(hello, 0);
  proto::LinkMessage config;
  *config.mutable_config() = ToDutConfig(firmware, control_period_s);
  sequencer.Stamp(config, 0);
  for (const proto::LinkMessage* message : {&hello, &config}) {
    if (auto sent = link.value()->Send(*message); !sent) return sent.error();
  }
  auto dut_hello = ReceiveWhileAlive(*link.value(), child.value(), start_ms, "hello");
  if (!dut_hello) return dut_hello.error();
  if (!dut_hello.value().has_hello() || dut_hello.value().hello().role() != proto::Hello::DUT) {
    return rig::MakeError("the dut process's first message is not a dut hello");
  }
  auto dut = std::unique_ptr<ProcessDut>(
      new ProcessDut(std::move(child).value(), std::move(link).value(), std::move(runner_bus),
                     std::move(forward_bus), options));
  dut->sequencer_ = sequencer;
  return dut;
}

ProcessDut::ProcessDut(ChildProcess child, std::unique_ptr<LinkConnection> link,
                       std::unique_ptr<rig::CanBus> runner_bus,
                       std::unique_ptr<rig::UdpBus> forward_bus, const ProcessDutOptions& options)
    : child_(std::move(child)),
      link_(std::move(link)),
      runner_bus_(std::move(runner_bus)),
      forward_bus_(std::move(forward_bus)),
      options_(options) {
  frames_.reserve(64);
}

ProcessDut::~ProcessDut() {
  if (!failure_) {
    proto::LinkMessage bye;
    bye.mutable_bye()->set_reason("run ended");
    sequencer_.Stamp(bye, 0);
    (void)link_->Send(bye, 100);
  }
  child_.Terminate(1000);
}

std::string ProcessDut::description() const {
  return "dut_fw in a dut_emu process (pid " + std::to_string(child_.pid()) +
         ") over the HIL link, lockstep";
}

std::vector<std::pair<std::string, double>> ProcessDut::link_metrics() const {
  std::vector<std::pair<std::string, double>> metrics =
      LinkCounterMetrics(link_->counters(), "link_rx_");
  metrics.emplace_back("link_tx_messages", static_cast<double>(link_->frames_sent()));
  metrics.emplace_back("link_commands_received", static_cast<double>(commands_received_));
  metrics.emplace_back("link_can_frames_forwarded", static_cast<double>(can_frames_forwarded_));
  metrics.emplace_back("link_watchdog_timeouts", static_cast<double>(watchdog_timeouts_));
  return metrics;
}

rig::Error ProcessDut::Failed(std::string message) {
  if (!failure_) failure_ = std::move(message);
  return rig::MakeError(*failure_);
}

std::string ProcessDut::ProcessGone() {
  // The link closes as the process dies; its exit status follows within moments.
  const timespec nap{0, 5'000'000};
  for (int waited_ms = 0; waited_ms < 200; waited_ms += 5) {
    if (auto exit = child_.PollExit()) return "dut process " + *exit;
    ::nanosleep(&nap, nullptr);
  }
  return "dut closed the link (process still running)";
}

void ProcessDut::Forward(const proto::LinkMessage& message) {
  if (failure_) return;
  if (auto sent = link_->Send(message); !sent) {
    (void)Failed(child_.PollExit() ? "dut process " + *child_.PollExit()
                                   : "link send failed: " + sent.error().message);
  }
}

void ProcessDut::SendImu(const ImuMessage& message) {
  ++counters_.imu_messages;
  Forward(ToLink(message));
}

void ProcessDut::SendVio(const VioMessage& message) {
  ++counters_.vio_messages;
  Forward(ToLink(message));
}

void ProcessDut::SendSetpoint(const SetpointMessage& message) { Forward(ToLink(message)); }

rig::Result<ActuatorMessage> ProcessDut::Step(std::uint64_t tick, std::int64_t now_ns) {
  if (failure_) return rig::MakeError(*failure_);
  frames_.clear();
  runner_bus_->Receive(now_ns, frames_);
  proto::LinkMessage request;
  proto::StepRequest* step = request.mutable_step();
  step->set_tick(tick);
  step->set_now_ns(now_ns);
  step->set_can_frames_sent(frames_.size());
  for (const rig::TimedCanFrame& timed : frames_) {
    // The sender time in the datagram is the arrival time too; the DUT takes it from the request.
    if (auto sent = forward_bus_->Send(timed.frame, timed.time_ns); !sent) {
      return Failed("forwarding a CAN frame to the dut: " + sent.error().message);
    }
    step->add_can_frame_time_ns(timed.time_ns);
  }
  can_frames_forwarded_ += frames_.size();
  counters_.can_frames_received += frames_.size();
  sequencer_.Stamp(request, now_ns);
  Forward(request);
  if (failure_) return rig::MakeError(*failure_);
  return AwaitCommand(tick);
}

rig::Result<ActuatorMessage> ProcessDut::AwaitCommand(std::uint64_t tick) {
  const int timeout_ms = Milliseconds(options_.answer_timeout_s);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    LinkReceived received =
        link_->Receive(static_cast<int>(std::min<std::int64_t>(left.count(), kPollSliceMs)));
    switch (received.status) {
      case LinkReceiveStatus::kTimeout:
        if (auto exit = child_.PollExit()) return Failed("dut process " + *exit);
        continue;
      case LinkReceiveStatus::kClosed:
        return Failed(ProcessGone());
      case LinkReceiveStatus::kLinkError:
        return Failed("dut sent a bad message (" + received.error + ")");
      case LinkReceiveStatus::kSocketError:
        return Failed("link to the dut failed: " + received.error);
      case LinkReceiveStatus::kMessage:
        break;
    }
    const proto::LinkMessage& message = received.message;
    if (message.has_bye()) {
      return Failed("dut ended the link: " + message.bye().reason());
    }
    if (!message.has_command()) {
      return Failed(
          "dut sent an unexpected " +
          proto::LinkMessage::descriptor()->FindFieldByNumber(message.payload_case())->name() +
          " message instead of the command for tick " + std::to_string(tick));
    }
    if (message.command().answers_sequence() != tick) {
      return Failed("dut answered tick " + std::to_string(message.command().answers_sequence()) +
                    " when asked for tick " + std::to_string(tick));
    }
    auto command = FromLink(message.command());
    if (!command) return Failed("dut sent a bad command: " + command.error().message);
    ++commands_received_;
    return command;
  }
  ++watchdog_timeouts_;
  if (auto exit = child_.PollExit()) return Failed("dut process " + *exit);
  return Failed("dut did not answer tick " + std::to_string(tick) + " within " +
                Seconds(options_.answer_timeout_s));
}

}  // namespace hilrig::host
