// How a run gets the DUT's command at a control tick: the one thing lockstep and real time do
// differently inside a tick. Lockstep asks and waits for the answer, which the plant takes at
// once. Real time asks without waiting; what arrives is collected between ticks (while the pacer
// waits) and the newest command is applied at the next control tick, none being a missed command.
// When a tick starts is the pacer's business, around the tick (host/runner/realtime_pacer.h); the
// tick itself calls the same two functions in both modes.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "host/dut/dut_port.h"
#include "host/runner/realtime_pacer.h"
#include "rig/result.h"

namespace hilrig::host {

class CommandExchange {
 public:
  virtual ~CommandExchange() = default;
  // Whether commands arrive between ticks (real time); when not, Arrived never has one and the
  // tick need not ask (lockstep's hot path makes no call for nothing).
  bool collects() const { return collects_; }
  // Both return true when they wrote a command into `command` (the runner's buffer for the next
  // one, so that the hot lockstep path moves the DUT's answer once), false when there is none;
  // an error is the DUT's failure and ends the run.
  //
  // At a control tick, before anything else: the command that arrived since the previous one, to
  // apply now (real time; lockstep: never any).
  virtual rig::Result<bool> Arrived(DutPort& dut, ActuatorMessage& command) = 0;
  // Asks for control tick `tick`'s command, the setpoint sent: lockstep has it at once, real time
  // later.
  virtual rig::Result<bool> Ask(DutPort& dut, std::uint64_t tick, std::int64_t now_ns,
                                ActuatorMessage& command) = 0;
  // Between ticks, while waiting for the next one: collects what the DUT sent (real time).
  virtual void Collect(DutPort& dut) { (void)dut; }

 protected:
  explicit CommandExchange(bool collects) : collects_(collects) {}

 private:
  bool collects_;
};

// Asks and waits: DutPort::Step.
class LockstepExchange final : public CommandExchange {
 public:
  LockstepExchange() : CommandExchange(false) {}
  rig::Result<bool> Arrived(DutPort& dut, ActuatorMessage& command) override;
  rig::Result<bool> Ask(DutPort& dut, std::uint64_t tick, std::int64_t now_ns,
                        ActuatorMessage& command) override;
};

// Asks without waiting (DutPort::RequestStep), collects with PollCommand, and counts each control
// tick on the pacer as served or missed. The first failure sticks.
class RealtimeExchange final : public CommandExchange {
 public:
  // `pacer` must outlive the exchange.
  explicit RealtimeExchange(RealtimePacer& pacer) : CommandExchange(true), pacer_(pacer) {}
  rig::Result<bool> Arrived(DutPort& dut, ActuatorMessage& command) override;
  rig::Result<bool> Ask(DutPort& dut, std::uint64_t tick, std::int64_t now_ns,
                        ActuatorMessage& command) override;
  void Collect(DutPort& dut) override;

 private:
  RealtimePacer& pacer_;
  std::optional<ActuatorMessage> arrived_;
  std::optional<rig::Error> failure_;
};

// The exchange for a run: real time with a pacer, else lockstep.
std::unique_ptr<CommandExchange> MakeCommandExchange(RealtimePacer* pacer);

}  // namespace hilrig::host
