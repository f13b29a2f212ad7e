#include "dut_emu/dut_emu_server.h"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <iterator>
#include <set>
#include <span>

#include "dut_emu/link_can_bus.h"
#include "dut_emu/staged_can_bus.h"
#include "host/dut/in_process_dut.h"
#include "host/link/dut_config_codec.h"
#include "host/link/hil_link_codec.h"
#include "host/link/hil_link_socket.h"
#include "host/link/shm_byte_stream.h"
#include "rig/command_args.h"
#include "rig/udp_bus.h"

namespace hilrig::dut_emu {
namespace {

using host::LinkReceiveStatus;

constexpr int kHandshakeTimeoutMs = 5000;
constexpr int kStopCheckMs = 100;  // how often a waiting DUT looks at stop_requested

// The wait for a real-time step's frames: one control period (the answer is late after that
// anyway), within sane bounds, and never longer than the lockstep wait.
std::chrono::nanoseconds RealtimeFrameWait(double control_period_s, int frame_wait_timeout_ms) {
  const double wait_s = std::clamp(control_period_s, 100e-6, 50e-3);
  return std::min<std::chrono::nanoseconds>(
      std::chrono::nanoseconds(static_cast<std::int64_t>(wait_s * 1e9)),
      std::chrono::milliseconds(frame_wait_timeout_ms));
}

// One session: the handshake, then message after message until the end.
class Session {
 public:
  // `link_bus`: the bus the frames of the step requests go to (owned by the bus given to Run);
  // null when a bus carries them.
  Session(const DutEmuOptions& options, const std::atomic<bool>* stop, std::ostream& log,
          std::unique_ptr<host::LinkConnection> link, LinkCanBus* link_bus)
      : options_(options), stop_(stop), log_(log), link_(std::move(link)), link_bus_(link_bus) {}

  int Run(std::unique_ptr<rig::CanBus> bus);

 private:
  bool Stopping() const { return stop_ != nullptr && stop_->load(); }
  int Fail(const std::string& reason);
  int Stopped();  // a clean end on request: a bye without error
  rig::Result<proto::LinkMessage> ReceiveWithin(int timeout_ms, const char* waiting_for);
  rig::Result<void> Handshake(std::unique_ptr<rig::CanBus> bus);
  // nullopt: go on; a value: the session ends with this exit code.
  std::optional<int> Handle(const proto::LinkMessage& message);
  std::optional<int> HandleStep(const proto::StepRequest& step);
  rig::Result<void> WaitForFrames(const proto::StepRequest& step);
  // The frames a step request carries, onto link_bus_; fails on frames no bus expects or that do
  // not decode.
  rig::Result<void> DeliverCarriedFrames(const proto::StepRequest& step);
  // The command with what the DUT had consumed when computing it.
  proto::LinkMessage Answer(const host::ActuatorMessage& command) const;

  const DutEmuOptions& options_;
  const std::atomic<bool>* stop_;
  std::ostream& log_;
  std::unique_ptr<host::LinkConnection> link_;
  host::LinkSequencer sequencer_;
  LinkCanBus* link_bus_;
  StagedCanBus* bus_ = nullptr;  // owned by dut_
  std::unique_ptr<host::InProcessDut> dut_;
  std::chrono::nanoseconds realtime_frame_wait_{0};
  // The sequence of the last message the DUT took on each stream (by DutInput alternative).
  std::array<std::optional<std::uint64_t>, host::kDutInputStreams> last_taken_;
  std::uint64_t frame_waits_expired_ = 0;
};

int Session::Fail(const std::string& reason) {
  log_ << "dut_emu: " << reason << "\n";
  proto::LinkMessage bye;
  bye.mutable_bye()->set_error(true);
  bye.mutable_bye()->set_reason(reason);
  sequencer_.Stamp(bye, 0);
  (void)link_->Send(bye, 200);  // best effort: the link may be what failed
  return kExitFailed;
}

rig::Result<proto::LinkMessage> Session::ReceiveWithin(int timeout_ms, const char* waiting_for) {
  for (int waited_ms = 0; waited_ms < timeout_ms; waited_ms += kStopCheckMs) {
    if (Stopping())
      return rig::MakeError("stopped while waiting for the " + std::string(waiting_for));
    host::LinkReceived received = link_->Receive(kStopCheckMs);
    if (received.status == LinkReceiveStatus::kMessage) return std::move(received.message);
    if (received.status == LinkReceiveStatus::kTimeout) continue;
    if (received.status == LinkReceiveStatus::kClosed) {
      return rig::MakeError("the runner closed the link before the " + std::string(waiting_for));
    }
    return host::LinkReceiveError(received, "link error while waiting for the " +
                                                std::string(waiting_for) + ": " + received.error);
  }
  return rig::MakeError("no " + std::string(waiting_for) + " from the runner within " +
                        std::to_string(timeout_ms) + " ms");
}

rig::Result<void> Session::Handshake(std::unique_ptr<rig::CanBus> bus) {
  proto::LinkMessage hello;
  hello.mutable_hello()->set_role(proto::Hello::DUT);
  hello.mutable_hello()->set_name("dut_emu " + std::to_string(::getpid()));
  if (options_.link_token) hello.mutable_hello()->set_token(options_.link_token->Proof());
  sequencer_.Stamp(hello, 0);
  if (auto sent = link_->Send(hello); !sent) return sent.error();
  auto runner_hello = ReceiveWithin(kHandshakeTimeoutMs, "runner's hello");
  if (!runner_hello) return runner_hello.error();
  if (runner_hello.value().has_bye()) {
    return rig::MakeError("the runner refused the link (" + runner_hello.value().bye().reason() +
                          "); the link token comes from --token-file or " +
                          host::kLinkTokenEnvironment);
  }
  if (!runner_hello.value().has_hello() ||
      runner_hello.value().hello().role() != proto::Hello::RUNNER) {
    return rig::MakeError("the runner's first message is not a runner hello");
  }
  auto config = ReceiveWithin(kHandshakeTimeoutMs, "firmware configuration");
  if (!config) return config.error();
  if (!config.value().has_config()) {
    return rig::MakeError("the runner's second message is not the firmware configuration");
  }
  auto setup = host::FromDutConfig(config.value().config());
  if (!setup) return rig::MakeError("bad firmware configuration: " + setup.error().message);
  // Every frame on the runner's UDP bus is announced; a real bus's frames go through as they come.
  const UnannouncedFrames unannounced =
      link_bus_ != nullptr || options_.can.scheme == rig::CanBusUri::Scheme::kUdp
          ? UnannouncedFrames::kEarly
          : UnannouncedFrames::kPassThrough;
  auto staged = std::make_unique<StagedCanBus>(std::move(bus), unannounced);
  bus_ = staged.get();
  dut_ = std::make_unique<host::InProcessDut>(setup.value().firmware, std::move(staged),
                                              setup.value().control_period_s);
  realtime_frame_wait_ =
      RealtimeFrameWait(setup.value().control_period_s, options_.frame_wait_timeout_ms);
  return {};
}

rig::Result<void> Session::WaitForFrames(const proto::StepRequest& step) {
  const std::uint64_t expected = step.can_frames_sent();
  if (static_cast<std::uint64_t>(step.can_frame_time_ns_size()) != expected) {
    return rig::MakeError("step request for tick " + std::to_string(step.tick()) + " announces " +
                          std::to_string(expected) + " CAN frames but carries " +
                          std::to_string(step.can_frame_time_ns_size()) + " frame times");
  }
  if (auto carried = DeliverCarriedFrames(step); !carried) return carried.error();
  bus_->Announce({step.can_frame_time_ns().data(), static_cast<std::size_t>(expected)});
  // The frames are already on their way over loopback; short naps until they are in, bounded.
  // Frames that came ahead of this request (a DUT that fell behind) are matched already.
  const std::chrono::nanoseconds wait =
      step.realtime() ? realtime_frame_wait_
                      : std::chrono::milliseconds(options_.frame_wait_timeout_ms);
  // On the OS's clock: the naps are real, and the wait bounds frames crossing a real socket (the
  // step's now_ns is the run's time, which stands still while this process waits).
  const auto deadline = std::chrono::steady_clock::now() + wait;
  const timespec nap{0, 20'000};
  bus_->Pump(step.now_ns());
  while (bus_->missing() > 0 && std::chrono::steady_clock::now() < deadline) {
    ::nanosleep(&nap, nullptr);
    bus_->Pump(step.now_ns());
  }
  if (step.realtime()) {
    // The runner did not wait; neither does the DUT. Late frames reach a later step.
    if (bus_->missing() > 0) ++frame_waits_expired_;
  } else if (bus_->missing() > 0 || bus_->early() > 0) {
    const std::uint64_t arrived = expected - bus_->missing() + bus_->early();
    return rig::MakeError("tick " + std::to_string(step.tick()) + ": " + std::to_string(arrived) +
                          " CAN frames arrived, the runner sent " + std::to_string(expected));
  }
  return {};
}

rig::Result<void> Session::DeliverCarriedFrames(const proto::StepRequest& step) {
  // Named only on failure: a step request comes every tick.
  const auto refused = [&step](const std::string& why) {
    return rig::MakeError("step request for tick " + std::to_string(step.tick()) + why);
  };
  if (link_bus_ == nullptr) {
    if (step.can_frame_size() == 0) return {};
    return refused(" carries CAN frames, but they reach this DUT on a bus");
  }
  if (static_cast<std::uint64_t>(step.can_frame_size()) != step.can_frames_sent()) {
    return refused(" announces " + std::to_string(step.can_frames_sent()) +
                   " CAN frames but carries " + std::to_string(step.can_frame_size()));
  }
  for (const std::string& datagram : step.can_frame()) {
    auto decoded = rig::DecodeUdpCanDatagram(
        {reinterpret_cast<const std::uint8_t*>(datagram.data()), datagram.size()});
    if (!decoded) return refused(": bad CAN frame: " + decoded.error().message);
    link_bus_->Deliver({&decoded.value().frame, 1});
  }
  return {};
}

std::optional<int> Session::HandleStep(const proto::StepRequest& step) {
  if (options_.exit_at_tick && step.tick() == *options_.exit_at_tick) {
    log_ << "dut_emu: test hook: exiting at tick " << step.tick() << "\n";
    return kExitTestHook;
  }
  if (options_.silent_at_tick && step.tick() == *options_.silent_at_tick) {
    log_ << "dut_emu: test hook: not answering tick " << step.tick() << "\n";
    return std::nullopt;
  }
  if (options_.garbage_at_tick && step.tick() == *options_.garbage_at_tick) {
    log_ << "dut_emu: test hook: answering tick " << step.tick() << " with garbage\n";
    // A length prefix of 8 and eight bytes that are no LinkMessage (field 15, wire type 7).
    (void)link_->SendBytes(std::string("\x08\x7f\xff\xff\xff\xff\xff\xff\xff", 9));
    return std::nullopt;
  }
  if (auto frames = WaitForFrames(step); !frames) return Fail(frames.error().message);
  auto command = dut_->Step(step.tick(), step.now_ns());
  if (!command) return Fail("control step failed: " + command.error().message);
  if (options_.wrong_tick_at_tick && step.tick() == *options_.wrong_tick_at_tick) {
    log_ << "dut_emu: test hook: answering tick " << step.tick() << " as a tick never asked for\n";
    command.value().answers_sequence = step.tick() + kWrongTickOffset;
  }
  if (auto sent = link_->Send(Answer(command.value())); !sent) {
    log_ << "dut_emu: " << sent.error().message << "\n";
    return kExitFailed;
  }
  return std::nullopt;
}

proto::LinkMessage Session::Answer(const host::ActuatorMessage& command) const {
  proto::LinkMessage answer = host::ToLink(command);
  proto::ActuatorCommand* fields = answer.mutable_command();
  for (std::size_t index = 0; index < last_taken_.size(); ++index) {
    if (last_taken_[index]) host::SetLastTakenSequence(*fields, index, *last_taken_[index]);
  }
  fields->set_can_frames_consumed(bus_->handed_over());
  fields->set_can_frame_waits_expired(frame_waits_expired_);
  fields->set_can_frames_dropped_foreign(bus_->counters().frames_dropped_foreign);
  fields->set_can_frames_dropped_malformed(bus_->counters().frames_dropped_malformed);
  const host::DutCounters counted = dut_->counters();
  proto::DutFrontEndCounters& front_end = *fields->mutable_front_end();
  front_end.set_can_frames_rejected(counted.can_frames_rejected);
  front_end.set_sensor_samples(counted.sensor_samples);
  front_end.set_sensor_sequence_gaps(counted.sensor_sequence_gaps);
  front_end.set_sensor_samples_lost(counted.sensor_samples_lost);
  front_end.set_tactile_samples_flagged(counted.tactile_samples_flagged);
  return answer;
}

std::optional<int> Session::Handle(const proto::LinkMessage& message) {
  if (std::optional<host::DutInput> input = host::DutInputFromLink(message)) {
    dut_->Send(*input);
    last_taken_[input->index()] = host::StampOf(*input).sequence;
    return std::nullopt;
  }
  switch (message.payload_case()) {
    case proto::LinkMessage::kStep:
      return HandleStep(message.step());
    case proto::LinkMessage::kBye:
      if (message.bye().error()) {
        log_ << "dut_emu: the runner ended the link: " << message.bye().reason() << "\n";
      }
      return kExitOk;
    default:
      return Fail(
          "unexpected " +
          proto::LinkMessage::descriptor()->FindFieldByNumber(message.payload_case())->name() +
          " message from the runner");
  }
}

int Session::Stopped() {
  log_ << "dut_emu: stopped by a signal\n";
  proto::LinkMessage bye;
  bye.mutable_bye()->set_reason("dut_emu stopped by a signal");
  sequencer_.Stamp(bye, 0);
  (void)link_->Send(bye, 200);
  return kExitOk;
}

int Session::Run(std::unique_ptr<rig::CanBus> bus) {
  if (auto ready = Handshake(std::move(bus)); !ready) {
    return Stopping() ? Stopped() : Fail(ready.error().message);
  }
  while (true) {
    if (Stopping()) return Stopped();
    host::LinkReceived received = link_->Receive(kStopCheckMs);
    switch (received.status) {
      case LinkReceiveStatus::kTimeout:
        continue;
      case LinkReceiveStatus::kMessage:
        if (std::optional<int> done = Handle(received.message)) return *done;
        continue;
      case LinkReceiveStatus::kClosed:
        log_ << "dut_emu: the runner closed the link without a bye\n";
        return kExitFailed;
      case LinkReceiveStatus::kLinkError:
      case LinkReceiveStatus::kSocketError:
        return Fail("link error: " + received.error);
    }
  }
}

}  // namespace

const char* const kDutEmuUsage =
    "usage: dut_emu (--link HOST:PORT --can URI | --link-shm FD [--can URI])\n"
    "               [--token-file PATH] [--frame-timeout-ms N]\n"
    "Connects to the runner's HIL link and runs the dut_fw controller behind it. It proves to\n"
    "the runner that it is the DUT with the runner's link token (32 hex digits), read from\n"
    "--token-file or else from the HILRIG_LINK_TOKEN environment variable. --link-shm FD is\n"
    "the shared-memory link the runner hands its child (no token; without --can the CAN\n"
    "frames ride in the link).\n"
    "Exit codes: 0 the runner said bye or a signal stopped it, 1 the link, the bus or the\n"
    "runner failed, 2 bad usage.\n";

namespace {

constexpr const char* kTestHooks[] = {"--test-garbage-at-tick", "--test-exit-at-tick",
                                      "--test-silent-at-tick", "--test-wrong-tick-at-tick"};

// The options both link kinds take: the token file, the frame wait, the test hooks.
rig::Result<DutEmuOptions> ParseCommonDutEmuArgs(const rig::CliArgs& cli, DutEmuOptions options) {
  if (const std::string* token_file = cli.Option("--token-file")) options.token_file = *token_file;
  if (const std::string* timeout = cli.Option("--frame-timeout-ms")) {
    auto ms = rig::ParseNumber<int>(*timeout, "--frame-timeout-ms");
    if (!ms || ms.value() <= 0) return rig::MakeError("--frame-timeout-ms must be positive");
    options.frame_wait_timeout_ms = ms.value();
  }
  std::optional<std::uint64_t>* hooks[] = {&options.garbage_at_tick, &options.exit_at_tick,
                                           &options.silent_at_tick, &options.wrong_tick_at_tick};
  for (std::size_t i = 0; i < std::size(kTestHooks); ++i) {
    const std::string* value = cli.Option(kTestHooks[i]);
    if (value == nullptr) continue;
    auto tick = rig::ParseNumber<std::uint64_t>(*value, kTestHooks[i]);
    if (!tick) return tick.error();
    *hooks[i] = tick.value();
  }
  return options;
}

}  // namespace

rig::Result<DutEmuOptions> ParseDutEmuArgs(const std::vector<std::string>& args) {
  std::set<std::string> allowed{"--link", "--link-shm", "--can", "--frame-timeout-ms",
                                "--token-file"};
  allowed.insert(std::begin(kTestHooks), std::end(kTestHooks));
  auto parsed = rig::ParseCliArgs(args, allowed);
  if (!parsed) return parsed.error();
  const rig::CliArgs& cli = parsed.value();
  if (!cli.positional.empty()) return rig::MakeError("unexpected argument " + cli.positional[0]);
  const std::string* link = cli.Option("--link");
  const std::string* link_shm = cli.Option("--link-shm");
  const std::string* can = cli.Option("--can");
  DutEmuOptions options;
  if (link_shm != nullptr) {
    if (link != nullptr) return rig::MakeError("--link and --link-shm exclude each other");
    auto fd = rig::ParseNumber<int>(*link_shm, "--link-shm");
    if (!fd || fd.value() < 0) return rig::MakeError("--link-shm \"" + *link_shm + "\": bad fd");
    options.link_shm_fd = fd.value();
    options.can_in_link = can == nullptr;
  } else if (link == nullptr || can == nullptr) {
    return rig::MakeError("--link and --can are required (or --link-shm FD)");
  }
  if (can != nullptr) {
    auto spec = rig::ParseCanBusUri(*can);
    if (!spec) return spec.error();
    options.can = spec.value();
  }
  if (link == nullptr) return ParseCommonDutEmuArgs(cli, options);
  const std::size_t colon = link->rfind(':');
  if (colon == std::string::npos || colon == 0) {
    return rig::MakeError("--link \"" + *link + "\": expected HOST:PORT");
  }
  auto port = rig::ParseNumber<std::uint16_t>(link->substr(colon + 1), "link port");
  if (!port || port.value() == 0) return rig::MakeError("--link \"" + *link + "\": bad port");
  options.link_host = link->substr(0, colon);
  options.link_port = port.value();
  return ParseCommonDutEmuArgs(cli, options);
}

rig::Result<host::LinkToken> LoadLinkToken(const DutEmuOptions& options,
                                           const char* environment_value) {
  if (!options.token_file.empty()) return host::ReadLinkTokenFile(options.token_file);
  const std::string variable = host::kLinkTokenEnvironment;
  if (environment_value == nullptr) {
    return rig::MakeError("no link token: pass --token-file PATH or set " + variable +
                          " (the runner sets it for the dut_emu it starts)");
  }
  auto token = host::ParseLinkToken(environment_value);
  if (!token) return rig::MakeError(variable + ": " + token.error().message);
  return token;
}

namespace {

// The link the options name: the inherited shared-memory mapping, or a TCP connection.
rig::Result<std::unique_ptr<host::LinkConnection>> OpenLink(
    const DutEmuOptions& options, const std::atomic<bool>* stop_requested) {
  if (options.link_shm_fd < 0) {
    return host::LinkConnection::Connect(options.link_host, options.link_port,
                                         options.connect_timeout_ms, stop_requested);
  }
  auto stream = host::ShmByteStream::Attach(options.link_shm_fd, host::ShmSide::kDut);
  if (!stream) return stream.error();
  return std::make_unique<host::LinkConnection>(std::move(stream).value(), "runner (shm)");
}

}  // namespace

int RunDutEmu(const DutEmuOptions& options, const std::atomic<bool>* stop_requested,
              std::ostream& log, std::unique_ptr<rig::CanBus> bus) {
  LinkCanBus* link_bus = nullptr;
  if (!bus && options.can_in_link) {
    auto carried = std::make_unique<LinkCanBus>();
    link_bus = carried.get();
    bus = std::move(carried);
  }
  if (!bus) {
    auto opened = rig::OpenCanBus(options.can);
    if (!opened) {
      log << "dut_emu: CAN bus: " << opened.error().message << "\n";
      return kExitFailed;
    }
    bus = std::move(opened).value();
  }
  auto link = OpenLink(options, stop_requested);
  if (!link) {
    log << "dut_emu: " << link.error().message << "\n";
    // A signal that asked us to stop is a clean end, as it is once the link is up.
    return link.error().code == rig::ErrorCode::kInterrupted ? kExitOk : kExitFailed;
  }
  Session session(options, stop_requested, log, std::move(link).value(), link_bus);
  return session.Run(std::move(bus));
}

}  // namespace hilrig::dut_emu
