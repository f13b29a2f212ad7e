// A stop request is an atomic flag that a signal handler (Ctrl-C, SIGTERM) or a caller sets and
// long work looks at between its steps; null means nobody can ask this work to stop.
#pragma once

#include <atomic>

namespace hilrig::rig {

inline bool StopRequested(const std::atomic<bool>* stop_requested) {
  return stop_requested != nullptr && stop_requested->load(std::memory_order_relaxed);
}

}  // namespace hilrig::rig
