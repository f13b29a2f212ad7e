#include "host/replay/replay_can_bus.h"

namespace hilrig::host {

rig::Result<void> ReplayCanBus::Send(const rig::CanFrame& frame, std::int64_t now_ns) {
  (void)frame;
  (void)now_ns;
  ++counters_.frames_sent;
  return {};
}

std::size_t ReplayCanBus::Receive(std::int64_t now_ns, std::vector<rig::TimedCanFrame>& out) {
  std::size_t received = 0;
  while (!queued_.empty() && queued_.front().time_ns <= now_ns) {
    out.push_back(queued_.front());
    queued_.pop_front();
    ++received;
  }
  counters_.frames_received += received;
  return received;
}

}  // namespace hilrig::host
