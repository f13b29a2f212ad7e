#include "rig/realtime_scheduling.h"

#include <pthread.h>
#include <sched.h>

#include <cstring>

namespace hilrig::rig {

ScopedFifoScheduling::ScopedFifoScheduling(int priority) {
  const std::string asked = "SCHED_FIFO priority " + std::to_string(priority);
  if (priority < kMinFifoPriority || priority > kMaxFifoPriority) {
    description_ = "default scheduler (" + asked + " refused: outside " +
                   std::to_string(kMinFifoPriority) + "-" + std::to_string(kMaxFifoPriority) + ")";
    return;
  }
  sched_param previous{};
  if (const int error = ::pthread_getschedparam(::pthread_self(), &previous_policy_, &previous);
      error != 0) {
    description_ = "default scheduler (" + asked + " refused: " + std::strerror(error) + ")";
    return;
  }
  previous_priority_ = previous.sched_priority;
  sched_param wanted{};
  wanted.sched_priority = priority;
  if (const int error = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &wanted);
      error != 0) {
    description_ = "default scheduler (" + asked + " refused: " + std::strerror(error) + ")";
    return;
  }
  granted_ = true;
  description_ = asked;
}

ScopedFifoScheduling::~ScopedFifoScheduling() {
  if (!granted_) return;
  sched_param previous{};
  previous.sched_priority = previous_priority_;
  (void)::pthread_setschedparam(::pthread_self(), previous_policy_, &previous);
}

}  // namespace hilrig::rig
