// A DUT on a serial line: a board's UART or USB CDC port, or an emulated MCU's USARTs. The HIL link
// runs on one byte stream in the framing of host/link/line_link.h, with the compact per-tick
// messages of proto/hil_link.proto (SerialStep / SerialCommand, floats, the setpoint only with the
// fields that changed). The tactile CAN frames that reach the runner's "dut" endpoint travel as a
// sensor node's UART bridge frames (dut_fw/sensor_node.h) on a second stream, the way a node's
// UART carries the bus to the flight controller on the vehicle; each step announces their bytes.
//
// Start shakes hands (a runner Hello every 100 ms until the DUT answers, a version check, the
// firmware configuration re-sent until the DUT answers with its TargetInfo). A lockstep Step
// re-sends the same SerialStep when no answer came within the retry timeout, so a lost or
// damaged frame costs a retry, not the run; garbage on the line is counted and skipped. The
// watchdog ends the run with a named error when no answer comes at all, the line closes, the DUT
// says Bye, or the emulator behind the line dies. Deadlines read the injected clock.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/dut/dut_port.h"
#include "host/dut/request_ledger.h"
#include "host/link/byte_stream.h"
#include "host/link/child_process.h"
#include "host/link/dut_firmware.h"
#include "host/link/hil_link_codec.h"
#include "host/link/line_link.h"
#include "host/link/link_token.h"
#include "proto/hil_link.pb.h"
#include "rig/can_bus.h"
#include "rig/clock.h"
#include "rig/ring_buffer.h"
#include "rig/value_counts.h"

namespace hilrig::host {

// What a serial DUT runs on.
struct SerialLines {
  std::unique_ptr<ByteStream> link;
  // The sensor nodes' UART bridge; null when none is wired (tactile frames are then counted and
  // dropped, unless `can` carries them).
  std::unique_ptr<ByteStream> bridge;
  // A CAN bus the DUT reads its sensors on itself (a board's own CAN port on a bench): the frames
  // go there instead of the bridge line, unannounced, and reach the DUT when the bus delivers
  // them, so such a run's sensor timing follows the wall clock. Null: the bridge line.
  std::unique_ptr<rig::CanBus> can;
  std::string can_uri;                   // what `can` is, for the description
  std::optional<ChildProcess> emulator;  // the process behind the lines, when there is one
  std::string description;               // "a board on /dev/ttyACM0 at 2000000 baud"
  // How long one byte takes to reach the DUT (10 bits at the baud rate; an emulator's USART is
  // slower). The retries wait twice the time the bytes they repeat need, on top of their timeout,
  // so a slow line is not taken for a lost frame.
  double byte_time_s = 0;
  // A line anyone on the host could reach (a TCP port): the DUT's hello must carry this token.
  std::optional<LinkToken> link_token;
};

// Opens the lines within `timeout_s` (an emulator takes a moment to open its ports).
using SerialLineOpener = std::function<rig::Result<SerialLines>(double timeout_s)>;

struct SerialDutOptions {
  double answer_timeout_s = 1.0;  // the watchdog: how long a step may go unanswered
  double start_timeout_s = 10.0;  // for the DUT to answer the hello and take the configuration
  double hello_interval_s = 0.1;
  double config_retry_s = 0.5;
  // Lockstep: the same SerialStep again when no answer came within this (a frame was lost).
  double step_retry_s = 0.05;
  // The watchdog's and the handshake's clock (it must outlive the DUT); null: a SteadyClock of
  // the DUT's own.
  const rig::Clock* clock = nullptr;
};

// Checks the options: positive finite timeouts, a retry shorter than the watchdog.
rig::Result<void> ValidateSerialDutOptions(const SerialDutOptions& options);

class SerialDut final : public DutPort {
 public:
  // `runner_bus` is the DUT's endpoint on the runner's emulated bus. Nothing opens until Start.
  SerialDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> runner_bus,
            double control_period_s, SerialLineOpener open_lines, const SerialDutOptions& options);
  ~SerialDut() override;

  rig::Result<void> Start() override;
  // Says Bye (unless the link failed), then ends and reaps an emulator.
  void Stop() override;
  void Send(const DutInput& input) override;
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override;
  void RequestStep(std::uint64_t tick, std::int64_t now_ns) override;
  rig::Result<std::optional<ActuatorMessage>> PollCommand() override;
  DutCounters counters() const override;
  std::string description() const override;
  std::vector<rig::Metric> link_metrics() const override;

  // The DUT's TargetInfo and the work per step its commands reported; nullopt before the DUT
  // took the configuration.
  std::optional<TargetSummary> target() const override;

 private:
  rig::Result<void> Handshake();
  // Sends `message` every `interval_ns` until `accept` takes an answer (true) or fails it.
  rig::Result<void> Exchange(
      const proto::LinkMessage& message, std::int64_t interval_ns, std::int64_t deadline_ns,
      const char* waiting_for,
      const std::function<rig::Result<bool>(const proto::LinkMessage&)>& accept);
  rig::Result<void> CheckRunning();
  rig::Error Failed(rig::Error error);
  rig::Error Failed(std::string message) { return Failed(rig::MakeError(std::move(message))); }
  // The line closed or failed: the emulator's exit when it died, else what the line said.
  rig::Error LineLost(const LineReceived& received);
  std::optional<std::string> EmulatorExit();
  // The tick's SerialStep: the buffered inputs and the bridge bytes written for it.
  rig::Result<proto::LinkMessage> BuildStep(std::uint64_t tick, std::int64_t now_ns, bool realtime);
  void AddInput(const DutInput& input, std::int64_t now_ns, proto::SerialStep& step);
  // The frames that reached the runner's endpoint, onto the bridge line (returns the bytes written,
  // which the step announces) or onto the DUT's own CAN bus (returns 0: nothing to wait for).
  rig::Result<std::uint32_t> ForwardBridgeFrames(std::int64_t now_ns, int timeout_ms);
  rig::Result<std::uint32_t> ForwardToCan();
  rig::Result<ActuatorMessage> AwaitCommand(const proto::LinkMessage& step, std::uint64_t tick);
  // What a received line event means while commands are awaited: the command it carries, nullptr
  // for another message (counted), or the failure (the line lost, a Bye). Not for kTimeout.
  rig::Result<const proto::SerialCommand*> CommandIn(const LineReceived& received);
  // A command received: its ActuatorMessage, after the counters and work it carries are kept.
  rig::Result<ActuatorMessage> TakeCommand(const proto::SerialCommand& command,
                                           std::int64_t now_ns);
  std::int64_t NowNs() const { return clock_->NowNs(); }
  // `seconds` plus twice the time `bytes` take on the line.
  std::int64_t RetryNs(double seconds, std::size_t bytes) const;

  DutFirmware firmware_;
  double control_period_s_;
  std::int64_t period_ns_;
  std::unique_ptr<rig::CanBus> runner_bus_;
  SerialLineOpener open_lines_;
  SerialDutOptions options_;
  std::unique_ptr<rig::SteadyClock> own_clock_;
  const rig::Clock* clock_;

  SerialLines lines_;
  std::unique_ptr<LineLink> link_;
  bool stopped_ = false;
  std::optional<rig::Error> failure_;
  LinkSequencer sequencer_;
  std::optional<proto::TargetInfo> target_info_;
  std::string dut_name_;

  std::vector<DutInput> pending_inputs_;
  std::optional<proto::SerialSetpoint> last_setpoint_;  // as last sent, every field set
  std::vector<rig::TimedCanFrame> frames_;
  std::vector<std::uint8_t> bridge_bytes_;
  RequestLedger ledger_;  // requests not answered yet, on clock_
  DutCounters counters_;
  proto::SerialDutCounters dut_counters_;
  rig::ValueCounts work_cycles_;

  std::uint64_t hellos_sent_ = 0;
  std::uint64_t configs_sent_ = 0;
  std::uint64_t steps_sent_ = 0;
  std::uint64_t step_retries_ = 0;
  std::uint64_t commands_received_ = 0;
  std::uint64_t unexpected_messages_ = 0;  // well-framed messages that were not an answer
  std::uint64_t bridge_frames_ = 0;
  std::uint64_t bridge_bytes_sent_ = 0;
  std::uint64_t bridge_frames_dropped_ = 0;  // no bridge wired, or a frame it cannot carry
  std::uint64_t can_frames_forwarded_ = 0;   // onto lines_.can
};

}  // namespace hilrig::host
