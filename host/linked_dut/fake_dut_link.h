// A DutLink that plays a script instead of moving bytes: what each Receive returns, how the
// process behind it ends, whether it repeats requests; and it records what the session asked of
// it. With a SimClock it lets the session's lockstep waits, retries, real-time polls and watchdog
// be tested without a process, a socket or wall time: every wait advances the clock instead.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "host/linked_dut/dut_link.h"
#include "rig/clock.h"

namespace hilrig::host {

class FakeDutLink final : public DutLink {
 public:
  // A request as the session handed it over.
  struct Sent {
    std::uint64_t tick = 0;
    std::int64_t now_ns = 0;
    std::size_t frames = 0;
    bool realtime = false;
  };

  // `clock` (may be null) moves on by each Receive's whole wait when nothing is scripted.
  explicit FakeDutLink(rig::SimClock* clock = nullptr) : clock_(clock) {}

  // --- the script ---
  // What Receive returns, in order, then kNothing; a kNothing waits the whole wait.
  std::deque<DutLinkEvent> events;
  // An answer to `tick` at the end of the script.
  void Answer(std::uint64_t tick) {
    events.push_back({DutLinkEventKind::kAnswer, tick, std::nullopt});
  }
  rig::Result<void> open_result;
  rig::Result<void> send_result;  // of every Input, Request and Resend
  std::optional<std::int64_t> resend_after;
  bool peer = false;
  std::optional<std::string> peer_exit;
  std::optional<proto::DutFrontEndCounters> front_end;  // the DUT's counts, when it reports them

  // --- what the session did ---
  std::vector<Sent> requests;
  std::uint64_t inputs = 0;
  std::uint64_t resends = 0;
  std::optional<bool> closed_with_goodbye;  // set by Close

  rig::Result<void> Open(const rig::Clock&) override { return open_result; }
  rig::Result<void> Input(const DutInput&, bool, std::int64_t) override {
    ++inputs;
    return send_result;
  }
  rig::Result<void> Request(const LinkRequest& request) override {
    requests.push_back({request.tick, request.now_ns, request.frames->size(), request.realtime});
    return send_result;
  }
  std::optional<std::int64_t> resend_after_ns() const override { return resend_after; }
  std::optional<proto::DutFrontEndCounters> front_end_counters() const override {
    return front_end;
  }
  rig::Result<void> Resend() override {
    ++resends;
    return send_result;
  }
  DutLinkEvent Receive(int timeout_ms) override {
    DutLinkEvent event;
    if (!events.empty()) {
      event = events.front();
      events.pop_front();
    }
    if (event.kind == DutLinkEventKind::kNothing && clock_) {
      clock_->AdvanceNs(std::int64_t{timeout_ms} * 1'000'000);
    }
    if (event.kind == DutLinkEventKind::kAnswer) answered_ = event.answers_tick;
    return event;
  }
  rig::Result<ActuatorMessage> TakeAnswer(std::int64_t arrival_wall_ns) override {
    ActuatorMessage command;
    command.stamp = {answered_, arrival_wall_ns};
    command.answers_sequence = answered_;
    return command;
  }
  bool has_peer() const override { return peer; }
  std::optional<std::string> PeerExit() override { return peer_exit; }
  void Close(bool goodbye) override { closed_with_goodbye = goodbye; }
  std::string description() const override { return "a scripted link"; }
  std::string metric_prefix() const override { return "fake_"; }
  std::vector<rig::Metric> metrics(bool) const override {
    return {rig::CountMetric("fake_requests", requests.size())};
  }

 private:
  rig::SimClock* clock_;
  std::uint64_t answered_ = 0;
};

}  // namespace hilrig::host
