// The requests a DUT behind a link has been sent and not answered yet, oldest first: the
// bookkeeping of ticks and answers, and the watchdog, written once for every such port
// (ProcessDut, SerialDut). In lockstep at most one request waits; in real time many may, and a DUT
// that falls behind may answer only its newest request, the older ones then counting as skipped.
// Times are the caller's, read from the clock it was given (a run's wall clock, or a fake), so the
// watchdog is tested without waiting. No function allocates once the ring is full-sized; each is
// O(1) but Take, which is O(requests it skips).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "rig/result.h"
#include "rig/ring_buffer.h"

namespace hilrig::host {

class RequestLedger {
 public:
  // Requests that may wait at once before the DUT counts as hopelessly behind.
  static constexpr std::size_t kMaxOutstanding = std::size_t{1} << 14;

  // `answer_timeout_ns`: how long the oldest request may wait before the watchdog fires.
  explicit RequestLedger(std::int64_t answer_timeout_ns) : answer_timeout_ns_(answer_timeout_ns) {}

  // Whether `tick` may be requested next: after the last tick requested, and with room. Fails with
  // "tick T requested after tick L" or "the dut fell N requests behind"; records nothing.
  rig::Result<void> CheckNext(std::uint64_t tick) const;
  // Records the request for `tick`, sent at `sent_ns` (CheckNext passed).
  void Add(std::uint64_t tick, std::int64_t sent_ns);

  enum class Outcome {
    kAnswers,         // it answers a waiting request (the older ones were skipped)
    kStale,           // a tick already answered (a retried request's twin, or answers going back)
    kNeverRequested,  // a tick no request asked for
  };
  struct Answer {
    Outcome outcome = Outcome::kNeverRequested;
    std::int64_t waited_ns = 0;  // kAnswers: from the request being sent to `arrival_ns`
  };
  // What an answer to `answers_tick` arriving at `arrival_ns` is; kAnswers takes its request, and
  // every older one as skipped.
  Answer Take(std::uint64_t answers_tick, std::int64_t arrival_ns);

  // The watchdog at `now_ns`: the oldest waiting request's tick once it has waited longer than
  // the answer timeout (counted as a watchdog timeout), nullopt otherwise.
  std::optional<std::uint64_t> Overdue(std::int64_t now_ns);
  // A timeout the caller's own wait found (a lockstep step), counted with the watchdog's.
  void CountTimeout() { ++watchdog_timeouts_; }

  std::optional<std::uint64_t> last_requested() const { return last_requested_; }
  std::optional<std::uint64_t> last_answered() const { return last_answered_; }

  std::uint64_t requests_skipped() const { return requests_skipped_; }
  std::uint64_t stale_answers() const { return stale_answers_; }
  std::uint64_t unrequested_answers() const { return unrequested_answers_; }
  std::uint64_t watchdog_timeouts() const { return watchdog_timeouts_; }

 private:
  struct Request {
    std::uint64_t tick = 0;
    std::int64_t sent_ns = 0;
  };

  std::int64_t answer_timeout_ns_;
  rig::RingBuffer<Request> outstanding_;
  std::optional<std::uint64_t> last_requested_;
  std::optional<std::uint64_t> last_answered_;
  std::uint64_t requests_skipped_ = 0;
  std::uint64_t stale_answers_ = 0;
  std::uint64_t unrequested_answers_ = 0;
  std::uint64_t watchdog_timeouts_ = 0;
};

// The watchdog's error for `tick`: "the dut did not answer for S (tick T)", kTimeout.
rig::Error OverdueError(std::uint64_t tick, double answer_timeout_s);

}  // namespace hilrig::host
