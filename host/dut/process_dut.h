// The DUT as its own process: a DutPort that starts dut_emu, talks to it over the HIL link (TCP on
// loopback) and hands it the tactile CAN frames over a loopback UDP CAN bus, in lockstep. Each
// Step forwards the frames that reached the runner's "dut" endpoint since the last step, asks for
// the tick's command (saying how many frames it forwarded and their arrival times, so the DUT
// process sees exactly what the in-process DUT would) and waits for the answer under a watchdog:
// no answer in time, a dead process, a closed link or a bad message end the run with an error that
// says which. The destructor ends and reaps the process.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/dut/dut_port.h"
#include "host/dut/firmware_config.h"
#include "host/link/child_process.h"
#include "host/link/hil_link_codec.h"
#include "host/link/hil_link_socket.h"
#include "rig/can_bus.h"
#include "rig/udp_bus.h"

namespace hilrig::host {

struct ProcessDutOptions {
  std::string dut_emu_path;       // empty: "dut_emu" next to the running executable
  double answer_timeout_s = 1.0;  // the watchdog on each Step's answer
  double start_timeout_s = 10.0;  // for the process to connect and say hello
  std::string listen_address = "127.0.0.1";
  std::vector<std::string> extra_args;  // appended to dut_emu's command line (test hooks)
};

// Checks the options: a positive finite timeout, an address.
rig::Result<void> ValidateProcessDutOptions(const ProcessDutOptions& options);

class ProcessDut final : public DutPort {
 public:
  // Starts dut_emu and completes the handshake (hello both ways, the firmware configuration).
  // `runner_bus` is the DUT's endpoint on the runner's emulated bus.
  static rig::Result<std::unique_ptr<ProcessDut>> Start(const DutFirmware& firmware,
                                                        std::unique_ptr<rig::CanBus> runner_bus,
                                                        double control_period_s,
                                                        const ProcessDutOptions& options);
  ~ProcessDut() override;

  void SendImu(const ImuMessage& message) override;
  void SendVio(const VioMessage& message) override;
  void SendSetpoint(const SetpointMessage& message) override;
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override;
  DutCounters counters() const override { return counters_; }
  std::string description() const override;
  std::vector<std::pair<std::string, double>> link_metrics() const override;

  pid_t pid() const { return child_.pid(); }

 private:
  ProcessDut(ChildProcess child, std::unique_ptr<LinkConnection> link,
             std::unique_ptr<rig::CanBus> runner_bus, std::unique_ptr<rig::UdpBus> forward_bus,
             const ProcessDutOptions& options);

  void Forward(const proto::LinkMessage& message);
  // The first failure sticks: every later Step reports it.
  rig::Error Failed(std::string message);
  std::string ProcessGone();
  rig::Result<ActuatorMessage> AwaitCommand(std::uint64_t tick);

  ChildProcess child_;
  std::unique_ptr<LinkConnection> link_;
  std::unique_ptr<rig::CanBus> runner_bus_;
  std::unique_ptr<rig::UdpBus> forward_bus_;
  ProcessDutOptions options_;
  LinkSequencer sequencer_;
  std::vector<rig::TimedCanFrame> frames_;
  DutCounters counters_;
  std::uint64_t can_frames_forwarded_ = 0;
  std::uint64_t commands_received_ = 0;
  std::uint64_t watchdog_timeouts_ = 0;
  std::optional<std::string> failure_;
};

}  // namespace hilrig::host
