#include "host/linked_dut/request_ledger.h"

#include <string>

#include "rig/number_text.h"

namespace hilrig::host {

rig::Result<void> RequestLedger::CheckNext(std::uint64_t tick) const {
  if (last_requested_ && tick <= *last_requested_) {
    return rig::MakeError("tick " + std::to_string(tick) + " requested after tick " +
                          std::to_string(*last_requested_));
  }
  if (outstanding_.size() >= kMaxOutstanding) {
    return rig::MakeError("the dut fell " + std::to_string(outstanding_.size()) +
                          " requests behind");
  }
  return {};
}

void RequestLedger::Add(std::uint64_t tick, std::int64_t sent_ns) {
  outstanding_.push_back({tick, sent_ns});
  last_requested_ = tick;
}

RequestLedger::Answer RequestLedger::Take(std::uint64_t answers_tick, std::int64_t arrival_ns) {
  if (last_answered_ && answers_tick <= *last_answered_) {
    ++stale_answers_;
    return {Outcome::kStale, 0};
  }
  while (!outstanding_.empty() && outstanding_.front().tick < answers_tick) {
    outstanding_.pop_front();
    ++requests_skipped_;
  }
  if (outstanding_.empty() || outstanding_.front().tick != answers_tick) {
    ++unrequested_answers_;
    return {Outcome::kNeverRequested, 0};
  }
  const std::int64_t waited_ns = arrival_ns - outstanding_.front().sent_ns;
  outstanding_.pop_front();
  last_answered_ = answers_tick;
  return {Outcome::kAnswers, waited_ns};
}

std::optional<std::uint64_t> RequestLedger::Overdue(std::int64_t now_ns) {
  if (outstanding_.empty() || now_ns - outstanding_.front().sent_ns <= answer_timeout_ns_) {
    return std::nullopt;
  }
  ++watchdog_timeouts_;
  return outstanding_.front().tick;
}

rig::Error OverdueError(std::uint64_t tick, double answer_timeout_s) {
  return rig::MakeError(rig::ErrorCode::kTimeout, "the dut did not answer for " +
                                                      rig::SecondsText(answer_timeout_s) +
                                                      " (tick " + std::to_string(tick) + ")");
}

}  // namespace hilrig::host
