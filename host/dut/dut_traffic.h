// A DUT's traffic as the runner exchanges it, for a run's log and its later replay: every input as
// it is sent, every CAN frame as the DUT takes it off its bus, every step asked for and every
// command that comes back. RecordingDutPort and RecordingCanBus sit between the runner and the DUT
// (and between the DUT and its bus endpoint), forward everything unchanged and tell a
// DutTrafficSink; neither the runner nor the DUT can tell they are there.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "host/dut/dut_port.h"
#include "rig/can_bus.h"
#include "rig/clock.h"

namespace hilrig::host {

// Where the traffic goes. Wall times are from the run's start, in real-time runs only (nullopt in
// lockstep, where the wall clock means nothing to the DUT). None of the calls fails: a sink keeps
// its own failure for the end of the run.
class DutTrafficSink {
 public:
  virtual ~DutTrafficSink() = default;
  virtual void Sent(const DutInput& input) = 0;
  // A frame the DUT received from its bus, stamped with when it finished arriving.
  virtual void Received(const rig::TimedCanFrame& frame) = 0;
  virtual void Asked(std::uint64_t tick, std::int64_t now_ns,
                     std::optional<std::int64_t> wall_ns) = 0;
  // The command that answers control tick `tick`, taken at simulated time `now_ns`.
  virtual void Answered(std::uint64_t tick, std::int64_t now_ns, const ActuatorMessage& command,
                        std::optional<std::int64_t> wall_ns) = 0;
};

// The DUT's bus endpoint, each received frame told to the sink. Everything else passes through.
class RecordingCanBus final : public rig::CanBus {
 public:
  // `sink` must outlive the bus.
  RecordingCanBus(std::unique_ptr<rig::CanBus> bus, DutTrafficSink& sink)
      : bus_(std::move(bus)), sink_(sink) {}
  rig::Result<void> Send(const rig::CanFrame& frame, std::int64_t now_ns) override {
    return bus_->Send(frame, now_ns);
  }
  std::size_t Receive(std::int64_t now_ns, std::vector<rig::TimedCanFrame>& out) override;
  void SetFilters(std::span<const rig::CanFilter> filters) override { bus_->SetFilters(filters); }
  void SetReceiveErrorFrames(bool enabled) override { bus_->SetReceiveErrorFrames(enabled); }
  void SetErrorFrameMask(std::uint32_t class_mask) override { bus_->SetErrorFrameMask(class_mask); }
  rig::Result<void> SetReceiveOwnFrames(bool enabled) override {
    return bus_->SetReceiveOwnFrames(enabled);
  }
  rig::BusState state() const override { return bus_->state(); }
  rig::BusCounters counters() const override { return bus_->counters(); }

 private:
  std::unique_ptr<rig::CanBus> bus_;
  DutTrafficSink& sink_;
};

// The DUT, each input, step and command told to the sink. `wall_clock` (real-time runs; null in
// lockstep) stamps the steps and commands with wall time from the port's construction. Forwarding
// costs one virtual call more per message and does not allocate, except for a real-time step's
// entry in the queue of steps awaiting their command.
class RecordingDutPort final : public DutPort {
 public:
  // `sink` and `wall_clock` must outlive the port.
  RecordingDutPort(std::unique_ptr<DutPort> dut, DutTrafficSink& sink,
                   const rig::Clock* wall_clock);

  rig::Result<void> Start() override { return dut_->Start(); }
  void SetRunFolder(const std::string& folder) override { dut_->SetRunFolder(folder); }
  void Stop() override { dut_->Stop(); }
  void Send(const DutInput& input) override {
    sink_.Sent(input);
    dut_->Send(input);
  }
  bool TakesNavigationSensors() const override { return dut_->TakesNavigationSensors(); }
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override;
  void RequestStep(std::uint64_t tick, std::int64_t now_ns) override;
  rig::Result<std::optional<ActuatorMessage>> PollCommand() override;
  std::vector<StreamLatency> response_latencies() const override {
    return dut_->response_latencies();
  }
  DutCounters counters() const override { return dut_->counters(); }
  std::string description() const override { return dut_->description(); }
  std::vector<rig::Metric> link_metrics() const override { return dut_->link_metrics(); }
  std::optional<TargetSummary> target() const override { return dut_->target(); }

 private:
  std::optional<std::int64_t> WallNs() const;

  struct Asked {
    std::uint64_t tick = 0;
    std::int64_t now_ns = 0;
  };
  std::unique_ptr<DutPort> dut_;
  DutTrafficSink& sink_;
  const rig::Clock* wall_clock_;
  std::int64_t wall_start_ns_ = 0;
  static constexpr std::size_t kMaxAwaitedSteps = 4096;
  std::deque<Asked> awaiting_;  // real time: steps asked whose command has not come yet
};

}  // namespace hilrig::host
