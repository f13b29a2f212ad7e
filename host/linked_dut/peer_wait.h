// The wait for a DUT to come up (to dial in, prove its token, say hello), written once for every
// linked DUT. It polls in slices and ends on its deadline, on the exit of the process the rig
// started, or on a stop request (a user's Ctrl-C), checked in that order before each slice, and
// the caller says in its own words which it was. What has come already wins over an exit or the
// deadline. The deadline is on the caller's clock: it bounds a real peer, so outside tests a clock
// that moves by itself.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "host/link/child_process.h"
#include "rig/clock.h"
#include "rig/result.h"

namespace hilrig::host {

enum class PeerWaitEnd {
  kStopped,     // a stop request came
  kPeerExited,  // the process the rig started ended; `exit` says how
  kTimedOut,    // the deadline passed
};

struct PeerWaitFailure {
  PeerWaitEnd end = PeerWaitEnd::kTimedOut;
  std::string exit;  // kPeerExited: "exited with status 3", "killed by signal 9"
};

struct PeerWait {
  const rig::Clock* clock = nullptr;  // required: the deadline's
  std::int64_t deadline_ns = 0;
  ChildProcess* child = nullptr;                      // null: nobody the rig started
  const std::atomic<bool>* stop_requested = nullptr;  // may be null
};

// The slice each attempt may wait, and how often a runner waiting on its DUT looks whether the
// process behind the link still lives.
inline constexpr int kPeerWaitSliceMs = 20;

// Calls `attempt(kPeerWaitSliceMs)` until it gives a result (nullopt: nothing yet, try again; a
// result, a value or an error, ends the wait) or the wait ends, which `describe` turns into the
// error: a stop request before each attempt, the process's exit and the deadline after it. Fails
// only as `attempt` or `describe` say.
template <typename Attempt, typename Describe>
auto WaitForPeer(const PeerWait& wait, Attempt attempt, Describe describe) ->
    typename decltype(attempt(0))::value_type {
  while (true) {
    if (wait.stop_requested != nullptr && wait.stop_requested->load()) {
      return describe(PeerWaitFailure{PeerWaitEnd::kStopped, {}});
    }
    if (auto done = attempt(kPeerWaitSliceMs)) return std::move(*done);
    if (wait.child != nullptr) {
      if (std::optional<std::string> exit = wait.child->PollExit()) {
        return describe(PeerWaitFailure{PeerWaitEnd::kPeerExited, *exit});
      }
    }
    if (wait.clock->NowNs() >= wait.deadline_ns) {
      return describe(PeerWaitFailure{PeerWaitEnd::kTimedOut, {}});
    }
  }
}

}  // namespace hilrig::host
