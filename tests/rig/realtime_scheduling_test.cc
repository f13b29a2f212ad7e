// ScopedFifoScheduling on the test's own thread (a fresh one per test, so the runner's thread keeps
// its policy whatever happens). Where the kernel grants SCHED_FIFO the policy is checked in effect
// and restored; where it refuses, the thread must be untouched and the description say why.
#include "rig/realtime_scheduling.h"

#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <thread>

namespace hilrig::rig {
namespace {

struct Policy {
  int policy = -1;
  int priority = -1;
  bool operator==(const Policy&) const = default;
};

Policy CurrentPolicy() {
  Policy current;
  sched_param param{};
  EXPECT_EQ(::pthread_getschedparam(::pthread_self(), &current.policy, &param), 0);
  current.priority = param.sched_priority;
  return current;
}

template <typename Body>
void OnFreshThread(Body body) {
  std::thread thread(body);
  thread.join();
}

TEST(ScopedFifoSchedulingTest, GrantedPolicyHoldsWhileInScopeAndIsRestoredAfter) {
  OnFreshThread([] {
    const Policy before = CurrentPolicy();
    {
      const ScopedFifoScheduling scheduling(10);
      if (scheduling.granted()) {
        EXPECT_EQ(CurrentPolicy(), (Policy{SCHED_FIFO, 10}));
        EXPECT_EQ(scheduling.description(), "SCHED_FIFO priority 10");
      } else {
        EXPECT_EQ(CurrentPolicy(), before);
        EXPECT_EQ(scheduling.description().rfind(
                      "default scheduler (SCHED_FIFO priority 10 refused: ", 0),
                  0u)
            << scheduling.description();
      }
    }
    EXPECT_EQ(CurrentPolicy(), before);
  });
}

TEST(ScopedFifoSchedulingTest, PriorityOutsideTheRangeIsRefusedAndTouchesNothing) {
  OnFreshThread([] {
    const Policy before = CurrentPolicy();
    for (const int priority : {kMinFifoPriority - 1, kMaxFifoPriority + 1, -5}) {
      const ScopedFifoScheduling scheduling(priority);
      EXPECT_FALSE(scheduling.granted()) << priority;
      EXPECT_NE(scheduling.description().find("refused: outside 1-99"), std::string::npos)
          << scheduling.description();
      EXPECT_EQ(CurrentPolicy(), before);
    }
  });
}

}  // namespace
}  // namespace hilrig::rig
