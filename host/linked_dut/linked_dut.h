// A DUT behind a link, whatever carries it: the one session every linked DUT runs (ProcessDut's
// process link, SerialDut's serial line), around a DutLink that only moves the bytes. Start opens
// the link; Send hands an input over; a lockstep Step sends the tick's request with the CAN frames
// that reached the runner's "dut" endpoint and waits for the answer, repeating the request on a
// lossy link; real-time RequestStep and PollCommand never wait, keep the newest answer and run the
// watchdog on every poll. Every answer is checked against the ticks requested (RequestLedger). The
// first failure sticks: a DUT that died (named by its exit), a link that closed, a broken message,
// a goodbye, or the watchdog ("the dut did not answer for S (tick T)"). Deadlines read the
// injected clock.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/dut/dut_port.h"
#include "host/linked_dut/dut_link.h"
#include "host/linked_dut/request_ledger.h"
#include "rig/can_bus.h"
#include "rig/clock.h"
#include "rig/duration_histogram.h"

namespace hilrig::host {

struct LinkedDutOptions {
  // Lockstep: Step waits for each answer; RequestStep and PollCommand fail. Real time: the
  // reverse, with the latencies measured; it needs `clock`.
  DutPacing pacing = DutPacing::kLockstep;
  // The watchdog: how long a lockstep Step waits for its answer, or how long the oldest
  // unanswered real-time request may wait.
  double answer_timeout_s = 1.0;
  // The watchdog's, the handshake's and the latencies' clock (it must outlive the DUT); null: a
  // SteadyClock of the DUT's own, for lockstep only. Its deadlines bound a real peer, so it is a
  // clock that moves by itself outside tests.
  const rig::Clock* clock = nullptr;
  // Named in the pacing errors: where the caller sets the pacing ("ProcessDutOptions::pacing").
  std::string pacing_option = "LinkedDutOptions::pacing";
};

// Checks the options: a positive finite watchdog of at most an hour, a clock for real time.
rig::Result<void> ValidateLinkedDutOptions(const LinkedDutOptions& options);

class LinkedDut : public DutPort {
 public:
  // `runner_bus` is the DUT's endpoint on the runner's emulated bus. Nothing opens until Start.
  LinkedDut(std::unique_ptr<DutLink> link, std::unique_ptr<rig::CanBus> runner_bus,
            const LinkedDutOptions& options);
  ~LinkedDut() override;

  // Opens the link (and the process behind it); once only.
  rig::Result<void> Start() override;
  void SetRunFolder(const std::string& folder) override { link_->SetRunFolder(folder); }
  // A goodbye unless the run failed, then the process behind the link ends.
  void Stop() override;
  // Never fails here: a link that cannot take the input fails the next Step or poll.
  void Send(const DutInput& input) override;
  // Lockstep. Fails with the sticky failure, or the tick's: not after the last one, the link
  // gone, no answer within the watchdog.
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override;
  // Real time; neither waits, and a failure sticks for the next poll.
  void RequestStep(std::uint64_t tick, std::int64_t now_ns) override;
  rig::Result<std::optional<ActuatorMessage>> PollCommand() override;
  // The link's input streams, then "command" (request to answer); none in lockstep.
  std::vector<StreamLatency> response_latencies() const override;
  DutCounters counters() const override;
  std::string description() const override { return link_->description(); }
  std::vector<rig::Metric> link_metrics() const override;
  std::optional<TargetSummary> target() const override { return link_->target(); }

 protected:
  DutLink& link() { return *link_; }
  const DutLink& link() const { return *link_; }

 private:
  bool realtime() const { return options_.pacing == DutPacing::kRealtime; }
  std::int64_t WallNs() const { return realtime() ? clock_->NowNs() : 0; }
  rig::Result<void> CheckRunning();
  rig::Error Failed(rig::Error error);
  // A link that could not send: the peer's exit when it died; in real time a closed link is let
  // be for a grace (the exit usually follows), otherwise the error sticks.
  void LinkFault(const rig::Error& error);
  // The link closed in lockstep: the process's exit when it follows within moments.
  rig::Error PeerGone(const rig::Error& closed);
  rig::Result<void> SendRequest(std::uint64_t tick, std::int64_t now_ns);
  rig::Result<ActuatorMessage> AwaitAnswer(std::uint64_t tick);
  // An answer to `answers_tick` checked against the requests (in lockstep only `waited` may be
  // answered): its command, nullopt for a repeated request's twin, or the failure.
  rig::Result<std::optional<ActuatorMessage>> TakeAnswer(std::uint64_t answers_tick,
                                                         std::optional<std::uint64_t> waited,
                                                         std::int64_t arrival_ns);
  // After a poll: the peer, the closed link and the watchdog, in that order.
  rig::Result<void> CheckAlive(std::int64_t now_ns);

  std::unique_ptr<DutLink> link_;
  std::unique_ptr<rig::CanBus> runner_bus_;
  LinkedDutOptions options_;
  std::unique_ptr<rig::SteadyClock> own_clock_;
  const rig::Clock* clock_;

  bool open_ = false;
  bool stopped_ = false;
  std::optional<rig::Error> failure_;
  // Real time: when the link was found closed, and how, while the peer's exit may still follow.
  std::optional<std::int64_t> closed_since_ns_;
  std::optional<rig::Error> closed_error_;
  std::vector<rig::TimedCanFrame> frames_;
  RequestLedger ledger_;
  DutCounters counters_;
  rig::DurationHistogram command_latency_;
  std::uint64_t commands_received_ = 0;
  std::uint64_t commands_superseded_ = 0;
};

}  // namespace hilrig::host
