// The DUT as its own process: a DutPort that starts dut_emu and talks to it over the HIL link, in
// lockstep. The link is shared memory by default (host/link/shm_byte_stream.h: a tick costs no
// system call, and the tactile CAN frames ride in the step request), or TCP on loopback with the
// frames on a loopback UDP CAN bus (DutLinkTransport::kTcp). Each Step hands over the frames that
// reached the runner's "dut" endpoint since the last step, asks for the tick's command (saying how
// many frames it forwarded and their arrival times, so the DUT process sees exactly what the
// in-process DUT would) and waits for the answer under a watchdog:
// no answer in time, a dead process, a closed link or a bad message end the run with an error that
// says which. Stop (or the destructor) ends and reaps the process.
//
// Real-time runs (RequestStep / PollCommand, with ProcessDutOptions::wall_clock set) share that
// path: a request goes out the same way without waiting, and each poll drains what the link holds
// without blocking, keeps the newest command, checks every answer against the ticks requested, and
// runs the watchdog on the wall clock (the oldest unanswered request, the process, the link). The
// wall send time of each IMU, VIO, setpoint message, CAN frame and request waits in a bounded ring;
// a command that says it consumed them turns them into response latencies. The latency is read
// when the command is polled, so it includes the wait for the poll.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "host/dut/dut_port.h"
#include "host/dut/firmware_config.h"
#include "host/dut/request_ledger.h"
#include "host/link/child_process.h"
#include "host/link/hil_link_codec.h"
#include "host/link/hil_link_socket.h"
#include "proto/hil_link.pb.h"
#include "rig/can_bus.h"
#include "rig/can_open.h"
#include "rig/clock.h"
#include "rig/duration_histogram.h"
#include "rig/ring_buffer.h"

namespace hilrig::host {

// What carries the HIL link to the dut_emu process (host/dut/process_dut_launch.h).
enum class DutLinkTransport {
  kSharedMemory,  // memfd rings inherited by the child: same host, fastest, no token
  kTcp,           // a TCP connection to listen_address, proven with the link token
};

struct ProcessDutOptions {
  DutLinkTransport transport = DutLinkTransport::kSharedMemory;
  std::string dut_emu_path;  // empty: "dut_emu" next to the running executable
  // `--dut exec:`: a program of the user's, started in dut_emu's place with `program_args` before
  // the link's arguments; it speaks the HIL link as dut_emu does. A path, or a name looked up in
  // PATH. Empty: dut_emu.
  std::string program;
  std::vector<std::string> program_args;
  // `--dut listen:`: start nothing, and wait (start_timeout_s) on listen_address:listen_port for a
  // DUT the user starts, which proves the token in token_file (written there with a new token
  // when the file does not exist). Over TCP, its CAN frames on the loopback UDP bus at
  // listen_port + 1 (it is node 1 of 2), or on can_uri.
  bool listen = false;
  std::uint16_t listen_port = 0;
  std::string token_file;
  // Where the wait for a DUT to dial in is announced (may be null), and what ends it early (may be
  // null): a user's Ctrl-C, so a run waiting for a DUT that never comes stops within a slice.
  std::ostream* notes = nullptr;
  const std::atomic<bool>* stop_requested = nullptr;
  // The watchdog: how long one Step waits for its answer (lockstep), or how long the oldest
  // unanswered request may wait in wall time (real time).
  double answer_timeout_s = 1.0;
  double start_timeout_s = 10.0;             // for the process to connect and say hello
  std::string listen_address = "127.0.0.1";  // kTcp only
  std::vector<std::string> extra_args;       // appended to dut_emu's command line (test hooks)
  // Lockstep: inputs go out with the tick's request and Step waits; RequestStep fails. Real time:
  // every message goes out at once, sends never wait for the socket, and the response latencies
  // are measured; it needs wall_clock.
  DutPacing pacing = DutPacing::kLockstep;
  // The clock of the watchdog and the latencies (it must outlive the ProcessDut); null: a
  // SteadyClock of the port's own, for lockstep only. Either way the watchdog's deadlines are on
  // a clock that moves by itself: they bound a real process.
  const rig::Clock* wall_clock = nullptr;
  // The bus the runner's CAN frames cross to the DUT: empty for a loopback UDP bus of the run's
  // own, or a socketcan:IFACE URI that the forwarder and dut_emu both open, as a bench is wired.
  // Nobody announces a real bus's frames to the DUT: they reach it when the bus delivers them, so
  // such a run's CAN timing follows the wall clock and real time is its meaningful mode.
  std::string can_uri;
  // Opens can_uri for the forwarder; unset: rig::OpenCanBus (tests hand in a bus of their own).
  std::function<rig::Result<std::unique_ptr<rig::CanBus>>(const std::string& uri)> open_can_bus;
};

// ProcessDutOptions::can_uri read by rig::ParseCanBusUri, refused unless two processes can share
// the bus it names: the errors name the URI and why.
rig::Result<rig::CanBusUri> ParseDutCanBusUri(const std::string& uri);

// Checks the options: a positive finite timeout, an address (other than the default only on the
// TCP link), a bus the DUT process can share.
rig::Result<void> ValidateProcessDutOptions(const ProcessDutOptions& options);

// "ADDRESS:PORT" a listening ProcessDut waits on.
std::string ListenEndpoint(const ProcessDutOptions& options);

class ProcessDut final : public DutPort {
 public:
  // `runner_bus` is the DUT's endpoint on the runner's emulated bus. Nothing runs until Start.
  ProcessDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> runner_bus,
             double control_period_s, const ProcessDutOptions& options);
  // Constructs and starts one (tests, tools).
  static rig::Result<std::unique_ptr<ProcessDut>> Launch(const DutFirmware& firmware,
                                                         std::unique_ptr<rig::CanBus> runner_bus,
                                                         double control_period_s,
                                                         const ProcessDutOptions& options);
  ~ProcessDut() override;

  // Starts dut_emu with a fresh link token in its environment and completes the handshake: the
  // first connection whose hello proves the token is the DUT (others are refused and counted in
  // link_peers_refused, and named in the description), which then gets the runner's hello and the
  // firmware configuration.
  rig::Result<void> Start() override;
  // Says goodbye on the link (unless it failed) and ends and reaps the process.
  void Stop() override;
  void Send(const DutInput& input) override;
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override;
  // Never block (see the file comment); PollCommand's errors stick like Step's.
  void RequestStep(std::uint64_t tick, std::int64_t now_ns) override;
  rig::Result<std::optional<ActuatorMessage>> PollCommand() override;
  // Each input stream by its kStream ("imu", "vio", "setpoint"), then "can" and "command"
  // (request to answer); none in lockstep.
  std::vector<StreamLatency> response_latencies() const override;
  DutCounters counters() const override { return counters_; }
  std::string description() const override;
  std::vector<rig::Metric> link_metrics() const override;

  // -1 before Start.
  pid_t pid() const { return child_ ? child_->pid() : -1; }

 private:
  // Wall send times of one stream's messages, keyed by sequence (CAN: frame count), until a
  // command covers them. Bounded: past kMaxPending the oldest is dropped, unmeasured.
  struct SendLog {
    struct Sent {
      std::uint64_t key = 0;
      std::int64_t wall_ns = 0;
    };
    rig::RingBuffer<Sent> pending;
    rig::DurationHistogram latency;
  };
  // Everything measured on the wall clock; only with one (real time).
  struct Latencies {
    std::array<SendLog, kDutInputStreams> inputs;  // by DutInput alternative
    SendLog can;                                   // keyed by the running count of frames forwarded
    rig::DurationHistogram command;
  };
  // The sticky failure, or one for a DUT not started or stopped.
  rig::Result<void> CheckRunning();
  // Sends the message; in lockstep an input only queues, to go out with the step request.
  void Forward(const proto::LinkMessage& message, bool input = false);
  // The first failure sticks: every later Step or poll reports it.
  rig::Error Failed(std::string message);
  rig::Error Failed(rig::Error error);
  std::string ProcessGone();
  // Forwards the frames that reached the runner's endpoint and sends the request for `tick`.
  rig::Result<void> SendStepRequest(std::uint64_t tick, std::int64_t now_ns, bool realtime);
  // Puts one received frame on its way: into the request (no forward bus) or onto the bus.
  rig::Result<void> HandOver(const rig::TimedCanFrame& timed, proto::StepRequest& step);
  rig::Result<ActuatorMessage> AwaitCommand(std::uint64_t tick);
  // A received message, judged: the command it carries (checked against the requests, latencies
  // recorded at `arrival_wall_ns`), or the failure it means. Not for kTimeout / kClosed.
  rig::Result<ActuatorMessage> TakeCommand(const LinkReceived& received,
                                           std::int64_t arrival_wall_ns);
  rig::Result<void> MatchRequest(std::uint64_t answers_tick, std::int64_t arrival_wall_ns);
  void RecordCoverage(const proto::ActuatorCommand& command, std::int64_t arrival_wall_ns);
  void LogSend(SendLog& log, std::uint64_t key, std::int64_t wall_ns);
  void Cover(SendLog& log, std::uint64_t up_to_key, std::int64_t arrival_wall_ns);
  // After draining a poll: the process, the closed link and the watchdog, in that order.
  rig::Result<void> CheckAlive(std::int64_t now_wall_ns);

  DutFirmware firmware_;
  double control_period_s_;
  // How a started child ended ("exited with status 3"); nullopt while it runs, or without a child
  // (a DUT that dialled in).
  std::optional<std::string> ChildExit();

  bool started_ = false;
  std::optional<ChildProcess> child_;     // set by Start, unless the DUT dialled in
  std::unique_ptr<LinkConnection> link_;  // set by Start
  bool stopped_ = false;
  std::unique_ptr<rig::CanBus> runner_bus_;
  std::unique_ptr<rig::CanBus> forward_bus_;  // null: the frames ride in the step requests
  ProcessDutOptions options_;
  LinkSequencer sequencer_;
  std::vector<rig::TimedCanFrame> frames_;
  DutCounters counters_;
  std::uint64_t can_frames_forwarded_ = 0;
  std::uint64_t commands_received_ = 0;
  std::optional<rig::Error> failure_;
  // Requests not answered yet, on the wall clock (0 without one: lockstep has no latencies).
  RequestLedger ledger_;
  std::optional<std::int64_t> link_closed_wall_ns_;  // real time: closed, exit status not in yet
  std::unique_ptr<Latencies> latencies_;             // real time only
  bool realtime() const { return options_.pacing == DutPacing::kRealtime; }
  rig::SteadyClock own_wall_clock_;  // the lockstep watchdog's, without one
  std::uint64_t commands_superseded_ = 0;
  std::uint64_t latency_samples_dropped_ = 0;
  std::uint64_t dut_frame_waits_expired_ = 0;
  std::uint64_t dut_frames_dropped_foreign_ = 0;    // forged datagrams the DUT's bus dropped
  std::uint64_t dut_frames_dropped_malformed_ = 0;  // datagrams no frame could be read from
  // Connections to the link port that did not prove the token, and who they were.
  std::uint64_t peers_refused_ = 0;
  std::string peers_refused_summary_;
};

}  // namespace hilrig::host
