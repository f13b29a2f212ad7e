#include "host/linked_dut/linked_dut.h"

#include <time.h>

#include <algorithm>
#include <cmath>

#include "host/link/hil_link_codec.h"
#include "host/linked_dut/peer_wait.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// A closed link usually means a dead process whose exit status follows within microseconds: a
// lockstep step waits this much for it, a real-time poll lets this much wall time pass, before
// it names the closed link instead.
constexpr std::int64_t kPeerExitGraceNs = 200'000'000;
// Bounds one poll's work on a DUT that floods the link.
constexpr int kMaxEventsPerPoll = 4096;

// Rounded up, so a wait never ends before its deadline; at most one poll slice.
int SliceUntil(std::int64_t now_ns, std::int64_t until_ns) {
  const std::int64_t ms = std::max<std::int64_t>(0, (until_ns - now_ns + 999'999) / 1'000'000);
  return static_cast<int>(std::min<std::int64_t>(ms, kPeerWaitSliceMs));
}

}  // namespace

rig::Result<void> ValidateLinkedDutOptions(const LinkedDutOptions& options) {
  if (options.pacing == DutPacing::kRealtime && options.clock == nullptr) {
    return rig::MakeError("a real-time dut needs a wall clock (" + options.pacing_option + ")");
  }
  const double seconds = options.answer_timeout_s;
  if (!std::isfinite(seconds) || seconds <= 0 || seconds > 3600) {
    return rig::MakeError("dut answer timeout " + rig::NumberText(seconds) +
                          " s: must be positive, finite and at most an hour");
  }
  return {};
}

LinkedDut::LinkedDut(std::unique_ptr<DutLink> link, std::unique_ptr<rig::CanBus> runner_bus,
                     const LinkedDutOptions& options)
    : link_(std::move(link)),
      runner_bus_(std::move(runner_bus)),
      options_(options),
      own_clock_(options.clock ? nullptr : std::make_unique<rig::SteadyClock>()),
      clock_(options.clock ? options.clock : own_clock_.get()),
      ledger_(rig::NsFromSeconds(options.answer_timeout_s)) {
  frames_.reserve(64);
}

LinkedDut::~LinkedDut() { Stop(); }

rig::Result<void> LinkedDut::Start() {
  if (open_ || stopped_ || failure_) return rig::MakeError("the dut was started already");
  if (auto valid = ValidateLinkedDutOptions(options_); !valid) return valid.error();
  if (auto opened = link_->Open(*clock_); !opened) {
    const rig::ErrorCode code = opened.error().code;
    if (code == rig::ErrorCode::kLinkClosed || code == rig::ErrorCode::kIo) {
      return PeerGone(opened.error());
    }
    return Failed(opened.error());
  }
  open_ = true;
  return {};
}

void LinkedDut::Stop() {
  if (stopped_) return;
  stopped_ = true;
  link_->Close(/*goodbye=*/open_ && !failure_);
}

rig::Error LinkedDut::Failed(rig::Error error) {
  if (!failure_) failure_ = std::move(error);
  return *failure_;
}

rig::Result<void> LinkedDut::CheckRunning() {
  if (failure_) return *failure_;
  if (!open_ || stopped_) {
    return Failed(rig::MakeError("the dut is not running (not started, or stopped)"));
  }
  return {};
}

void LinkedDut::LinkFault(const rig::Error& error) {
  if (auto exit = link_->PeerExit()) {
    (void)Failed(rig::MakeError(*exit));
  } else if (realtime() && error.code == rig::ErrorCode::kLinkClosed) {
    // Most likely a process still dying: the next polls name it, or the closed link.
    if (!closed_since_ns_) {
      closed_since_ns_ = clock_->NowNs();
      closed_error_ = error;
    }
  } else {
    (void)Failed(error);
  }
}

rig::Error LinkedDut::PeerGone(const rig::Error& closed) {
  if (link_->has_peer()) {
    const timespec nap{0, 5'000'000};
    for (std::int64_t waited_ns = 0; waited_ns < kPeerExitGraceNs; waited_ns += nap.tv_nsec) {
      if (auto exit = link_->PeerExit()) return Failed(rig::MakeError(*exit));
      ::nanosleep(&nap, nullptr);
    }
  }
  return Failed(closed);
}

void LinkedDut::Send(const DutInput& input) {
  counters_.Count(input);
  if (failure_ || !open_ || stopped_) return;
  if (auto taken = link_->Input(input, realtime(), WallNs()); !taken) LinkFault(taken.error());
}

rig::Result<void> LinkedDut::SendRequest(std::uint64_t tick, std::int64_t now_ns) {
  if (auto running = CheckRunning(); !running) return running.error();
  if (auto next = ledger_.CheckNext(tick); !next) return Failed(next.error());
  frames_.clear();
  runner_bus_->Receive(now_ns, frames_);
  counters_.can_frames_received += frames_.size();
  const std::int64_t wall_ns = WallNs();
  if (auto sent = link_->Request({tick, now_ns, &frames_, realtime(), wall_ns}); !sent) {
    LinkFault(sent.error());
    if (failure_) return *failure_;
  }
  ledger_.Add(tick, wall_ns);
  return {};
}

rig::Result<ActuatorMessage> LinkedDut::Step(std::uint64_t tick, std::int64_t now_ns) {
  if (auto sent = SendRequest(tick, now_ns); !sent) return sent.error();
  return AwaitAnswer(tick);
}

rig::Result<ActuatorMessage> LinkedDut::AwaitAnswer(std::uint64_t tick) {
  const std::int64_t start_ns = clock_->NowNs();
  const std::int64_t deadline_ns = start_ns + rig::NsFromSeconds(options_.answer_timeout_s);
  const std::optional<std::int64_t> resend_after_ns = link_->resend_after_ns();
  std::int64_t resend_ns = resend_after_ns ? start_ns + *resend_after_ns : deadline_ns;
  for (std::int64_t now_ns = start_ns; now_ns < deadline_ns; now_ns = clock_->NowNs()) {
    if (resend_after_ns && now_ns >= resend_ns) {
      if (auto resent = link_->Resend(); !resent) {
        LinkFault(resent.error());
        return *failure_;
      }
      resend_ns = now_ns + *resend_after_ns;
    }
    const DutLinkEvent event = link_->Receive(SliceUntil(now_ns, std::min(resend_ns, deadline_ns)));
    switch (event.kind) {
      case DutLinkEventKind::kNothing:
        if (auto exit = link_->PeerExit()) return Failed(rig::MakeError(*exit));
        continue;
      case DutLinkEventKind::kIgnored:
        continue;
      case DutLinkEventKind::kClosed:
        return PeerGone(*event.error);
      case DutLinkEventKind::kFailed:
        return Failed(*event.error);
      case DutLinkEventKind::kAnswer:
        break;
    }
    auto answer = TakeAnswer(event.answers_tick, tick, WallNs());
    if (!answer) return answer.error();
    if (answer.value()) return std::move(*answer.value());
  }
  ledger_.CountTimeout();
  if (auto exit = link_->PeerExit()) return Failed(rig::MakeError(*exit));
  return Failed(rig::MakeError(rig::ErrorCode::kTimeout,
                               "the dut did not answer tick " + std::to_string(tick) + " within " +
                                   rig::SecondsText(options_.answer_timeout_s) +
                                   link_->timeout_detail()));
}

rig::Result<std::optional<ActuatorMessage>> LinkedDut::TakeAnswer(
    std::uint64_t answers_tick, std::optional<std::uint64_t> waited, std::int64_t arrival_ns) {
  const std::optional<std::uint64_t> last_answered = ledger_.last_answered();
  const std::optional<std::uint64_t> last_requested = ledger_.last_requested();
  // In lockstep only the waited tick may be answered: a later one is refused before the ledger
  // would count the waited one as skipped.
  const RequestLedger::Answer answer = waited && answers_tick > *waited
                                           ? RequestLedger::Answer{}
                                           : ledger_.Take(answers_tick, arrival_ns);
  switch (answer.outcome) {
    case RequestLedger::Outcome::kAnswers:
      break;
    case RequestLedger::Outcome::kStale:
      if (link_->resend_after_ns()) return std::optional<ActuatorMessage>();  // a repeat's twin
      return Failed(LinkProtocolError(
          LinkErrorKind::kOutOfOrder,
          "the dut answered tick " + std::to_string(answers_tick) + " after tick " +
              std::to_string(last_answered.value_or(0)) + " (answers went backwards)"));
    case RequestLedger::Outcome::kNeverRequested:
      return Failed(
          LinkProtocolError(LinkErrorKind::kOutOfOrder,
                            "the dut answered tick " + std::to_string(answers_tick) +
                                ", which was never requested (last request: tick " +
                                (last_requested ? std::to_string(*last_requested) : "none") + ")"));
  }
  if (realtime()) command_latency_.Add(answer.waited_ns);
  auto command = link_->TakeAnswer(arrival_ns);
  if (!command) return Failed(command.error());
  ++commands_received_;
  return std::optional<ActuatorMessage>(std::move(command).value());
}

void LinkedDut::RequestStep(std::uint64_t tick, std::int64_t now_ns) {
  if (failure_) return;
  if (!realtime()) {
    (void)Failed(rig::MakeError("a real-time step request to a lockstep dut (" +
                                options_.pacing_option + ")"));
    return;
  }
  (void)SendRequest(tick, now_ns);  // a failure sticks for the next poll
}

rig::Result<std::optional<ActuatorMessage>> LinkedDut::PollCommand() {
  if (auto running = CheckRunning(); !running) return running.error();
  if (!realtime()) {
    return Failed(
        rig::MakeError("a real-time poll of a lockstep dut (" + options_.pacing_option + ")"));
  }
  const std::int64_t now_ns = clock_->NowNs();
  std::optional<ActuatorMessage> newest;
  for (int events = 0; events < kMaxEventsPerPoll && !closed_since_ns_; ++events) {
    const DutLinkEvent event = link_->Receive(0);
    if (event.kind == DutLinkEventKind::kNothing) break;
    if (event.kind == DutLinkEventKind::kIgnored) continue;
    if (event.kind == DutLinkEventKind::kClosed) {
      closed_since_ns_ = now_ns;
      closed_error_ = event.error;
      break;
    }
    if (event.kind == DutLinkEventKind::kFailed) return Failed(*event.error);
    auto answer = TakeAnswer(event.answers_tick, std::nullopt, now_ns);
    if (!answer) return answer.error();
    if (!answer.value()) continue;
    if (newest) ++commands_superseded_;
    newest = std::move(answer).value();
  }
  if (auto alive = CheckAlive(now_ns); !alive) return alive.error();
  return newest;
}

rig::Result<void> LinkedDut::CheckAlive(std::int64_t now_ns) {
  if (auto exit = link_->PeerExit()) return Failed(rig::MakeError(*exit));
  if (closed_since_ns_) {
    // Nothing can answer any more; name the closed link unless the exit turns up in time.
    if (now_ns - *closed_since_ns_ < kPeerExitGraceNs) return {};
    return Failed(*closed_error_);
  }
  if (auto tick = ledger_.Overdue(now_ns)) {
    return Failed(OverdueError(*tick, options_.answer_timeout_s));
  }
  return {};
}

std::vector<StreamLatency> LinkedDut::response_latencies() const {
  if (!realtime()) return {};
  std::vector<StreamLatency> latencies = link_->input_latencies();
  latencies.push_back({"command", command_latency_.Summary()});
  return latencies;
}

DutCounters LinkedDut::counters() const {
  DutCounters counters = counters_;
  counters.sensor_bytes_missing = link_->sensor_bytes_missing();
  if (const std::optional<proto::DutFrontEndCounters> dut = link_->front_end_counters()) {
    counters.front_end_counted = true;
    counters.can_frames_rejected = dut->can_frames_rejected();
    counters.sensor_samples = dut->sensor_samples();
    counters.sensor_sequence_gaps = dut->sensor_sequence_gaps();
    counters.sensor_samples_lost = dut->sensor_samples_lost();
    counters.tactile_samples_flagged = dut->tactile_samples_flagged();
  }
  return counters;
}

std::vector<rig::Metric> LinkedDut::link_metrics() const {
  std::vector<rig::Metric> metrics = link_->metrics(realtime());
  if (metrics.empty()) return metrics;  // a link that never opened has nothing to report
  const std::string prefix = link_->metric_prefix();
  for (const auto& [name, value] : {std::pair{"commands_received", commands_received_},
                                    {"watchdog_timeouts", ledger_.watchdog_timeouts()},
                                    {"requests_skipped", ledger_.requests_skipped()},
                                    {"stale_answers", ledger_.stale_answers()},
                                    {"unrequested_answers", ledger_.unrequested_answers()}}) {
    metrics.push_back(rig::CountMetric(prefix + name, value));
  }
  if (realtime()) {
    metrics.push_back(rig::CountMetric(prefix + "commands_superseded", commands_superseded_));
  }
  return metrics;
}

}  // namespace hilrig::host
