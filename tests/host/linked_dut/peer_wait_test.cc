// The one wait for a DUT to come up: what came wins, then the process's exit, the deadline on the
// caller's clock, and a stop request, each reported as itself.
#include "host/linked_dut/peer_wait.h"

#include <gtest/gtest.h>

#include <atomic>
#include <optional>

#include "rig/clock.h"

namespace hilrig::host {
namespace {

rig::Result<int> Describe(const PeerWaitFailure& failure) {
  switch (failure.end) {
    case PeerWaitEnd::kStopped:
      return rig::MakeError(rig::ErrorCode::kInterrupted, "stopped");
    case PeerWaitEnd::kPeerExited:
      return rig::MakeError("peer " + failure.exit);
    case PeerWaitEnd::kTimedOut:
      break;
  }
  return rig::MakeError(rig::ErrorCode::kTimeout, "timed out");
}

TEST(PeerWaitTest, WhatComesEndsTheWaitAndATimeoutIsOnTheCallersClock) {
  rig::SimClock clock;
  int attempts = 0;
  const auto third = WaitForPeer(
      PeerWait{&clock, 1'000'000'000},
      [&](int slice_ms) -> std::optional<rig::Result<int>> {
        EXPECT_EQ(slice_ms, kPeerWaitSliceMs);
        if (++attempts < 3) return std::nullopt;
        return rig::Result<int>(42);
      },
      Describe);
  ASSERT_TRUE(third);
  EXPECT_EQ(third.value(), 42);

  const auto never = WaitForPeer(
      PeerWait{&clock, 100'000'000},
      [&](int slice_ms) -> std::optional<rig::Result<int>> {
        clock.AdvanceNs(std::int64_t{slice_ms} * 1'000'000);
        return std::nullopt;
      },
      Describe);
  ASSERT_FALSE(never);
  EXPECT_EQ(never.error().code, rig::ErrorCode::kTimeout);
  EXPECT_EQ(clock.NowNs(), 100'000'000);  // five slices of 20 ms, no more
}

TEST(PeerWaitTest, AStopRequestAndAnExitedProcessEndItByName) {
  rig::SimClock clock;
  std::atomic<bool> stop{true};
  const auto stopped = WaitForPeer(
      PeerWait{&clock, 1'000'000'000, nullptr, &stop},
      [](int) -> std::optional<rig::Result<int>> { return rig::Result<int>(1); }, Describe);
  ASSERT_FALSE(stopped);
  EXPECT_EQ(stopped.error().code, rig::ErrorCode::kInterrupted);

  auto child = ChildProcess::Spawn({"/bin/sh", "-c", "exit 3"});
  ASSERT_TRUE(child) << child.error().message;
  const rig::SteadyClock wall;
  const auto exited = WaitForPeer(
      PeerWait{&wall, wall.NowNs() + 5'000'000'000, &child.value()},
      [](int slice_ms) -> std::optional<rig::Result<int>> {
        (void)slice_ms;
        return std::nullopt;
      },
      Describe);
  ASSERT_FALSE(exited);
  EXPECT_EQ(exited.error().message, "peer exited with status 3");
}

}  // namespace
}  // namespace hilrig::host
