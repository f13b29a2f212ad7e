// The conformance suite every CanBus backend runs, so that the runner, emulators and DUT can
// switch between the emulated bus, loopback UDP, SocketCAN and gs_usb without noticing. The tests
// (in can_bus_conformance.cc) only use the CanBus interface plus the small CanBusBackend factory
// below, which each backend implements in its own test file.
//
// To run the suite on a backend:
//
//   #include "tests/rig/can_bus_conformance.h"
//
//   class MyBackend final : public hilrig::rig::CanBusBackend { ... };
//
//   INSTANTIATE_TEST_SUITE_P(
//       MyBus, CanBusConformanceTest,
//       ::testing::Values(hilrig::rig::CanBusBackendParam{
//           "my_bus", [] { return std::make_unique<MyBackend>(); }}),
//       hilrig::rig::CanBusBackendParamName);
//
// (inside namespace hilrig::rig, or with CanBusConformanceTest qualified). can_bus_conformance.cc,
// which holds the tests, must be linked into the same test executable. A backend that cannot run
// here (no AF_CAN, no vcan device, no adapter plugged in) returns the reason from SkipReason() and
// every test skips with it; a backend that can run but fails to make endpoints fails the tests.
//
// Negative checks ("this frame must not arrive") never wait on wall time: the sender follows the
// frame with a marker frame that must arrive, and since every backend keeps one sender's frames in
// order, whatever has not arrived before the marker is not coming.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "rig/can_bus.h"
#include "rig/can_frame.h"
#include "rig/result.h"

namespace hilrig::rig {

class CanBusBackend {
 public:
  virtual ~CanBusBackend() = default;

  // Shown in test names and failure messages, e.g. "emulated" or "socketcan vcan0".
  virtual std::string Name() const = 0;
  // Why this backend cannot run on this machine, or nullopt if it can.
  virtual std::optional<std::string> SkipReason() const = 0;
  // `count` endpoints on one bus, each seeing every other's frames. Called at most once per
  // backend object (one test); the backend must outlive the endpoints.
  virtual Result<std::vector<std::unique_ptr<CanBus>>> MakeEndpoints(std::size_t count) = 0;

  // The time to pass to Send and Receive.
  virtual std::int64_t NowNs() const = 0;
  // Lets time pass between polls: simulated backends advance their clock by dt_ns, real ones may
  // advance a counter and yield so the OS can deliver. It is called in bounded loops, so it must
  // not sleep.
  virtual void Advance(std::int64_t dt_ns) = 0;

  // Whether CAN FD frames can be sent (e.g. false for a classic-only adapter).
  virtual bool SupportsFd() const { return true; }
  // Puts an error frame on the bus, by default by sending it from `via` (one of the endpoints).
  // A backend that cannot returns an error and the error frame tests skip with it.
  virtual Result<void> InjectErrorFrame(CanBus& via, const CanFrame& error_frame) {
    return via.Send(error_frame, NowNs());
  }
};

struct CanBusBackendParam {
  std::string name;  // letters, digits and underscores: it becomes part of the test name
  std::function<std::unique_ptr<CanBusBackend>()> make;
};

inline std::string CanBusBackendParamName(
    const ::testing::TestParamInfo<CanBusBackendParam>& info) {
  return info.param.name;
}

inline void PrintTo(const CanBusBackendParam& param, std::ostream* out) { *out << param.name; }

class CanBusConformanceTest : public ::testing::TestWithParam<CanBusBackendParam> {
 protected:
  // Bounds every wait: long enough for a real bus under load, short enough to fail fast.
  static constexpr int kMaxPolls = 20'000;
  static constexpr std::int64_t kPollStepNs = 100'000;

  void SetUp() override;

  // The endpoints, or none (after recording a failure) if the backend could not make them.
  std::vector<std::unique_ptr<CanBus>> MakeEndpoints(std::size_t count);
  Result<void> Send(CanBus& endpoint, const CanFrame& frame);
  // Polls until `count` frames arrived or the poll budget is spent; returns what arrived.
  std::vector<TimedCanFrame> ReceiveFrames(CanBus& endpoint, std::size_t count);
  // Lets the bus settle, then sends the marker frame from `sender`.
  void SendMarker(CanBus& sender, const CanFrame& marker);
  // Everything that arrived before `marker`; records a failure if the marker never comes.
  std::vector<TimedCanFrame> ReceiveUntil(CanBus& endpoint, const CanFrame& marker);

  std::unique_ptr<CanBusBackend> backend_;
};

// Defined here, inline, so that a backend's test file links even where can_bus_conformance.cc is
// missing from its executable; CanBusConformanceSuiteTest then fails and says so.

inline void CanBusConformanceTest::SetUp() {
  backend_ = GetParam().make();
  ASSERT_NE(backend_, nullptr) << GetParam().name << ": factory returned no backend";
  if (const std::optional<std::string> reason = backend_->SkipReason()) {
    GTEST_SKIP() << backend_->Name() << ": " << *reason;
  }
}

inline std::vector<std::unique_ptr<CanBus>> CanBusConformanceTest::MakeEndpoints(
    std::size_t count) {
  Result<std::vector<std::unique_ptr<CanBus>>> endpoints = backend_->MakeEndpoints(count);
  if (!endpoints) {
    ADD_FAILURE() << backend_->Name() << ": " << endpoints.error().message;
    return {};
  }
  EXPECT_EQ(endpoints.value().size(), count) << backend_->Name();
  return std::move(endpoints).value();
}

inline Result<void> CanBusConformanceTest::Send(CanBus& endpoint, const CanFrame& frame) {
  return endpoint.Send(frame, backend_->NowNs());
}

inline std::vector<TimedCanFrame> CanBusConformanceTest::ReceiveFrames(CanBus& endpoint,
                                                                       std::size_t count) {
  std::vector<TimedCanFrame> received;
  for (int poll = 0; poll < kMaxPolls && received.size() < count; ++poll) {
    backend_->Advance(kPollStepNs);
    endpoint.Receive(backend_->NowNs(), received);
  }
  return received;
}

inline void CanBusConformanceTest::SendMarker(CanBus& sender, const CanFrame& marker) {
  // Time for the frames before it to be on the wire, so arbitration cannot put the marker first.
  backend_->Advance(kPollStepNs);
  const Result<void> sent = Send(sender, marker);
  ASSERT_TRUE(sent.ok()) << backend_->Name() << ": marker not sent: " << sent.error().message;
}

inline std::vector<TimedCanFrame> CanBusConformanceTest::ReceiveUntil(CanBus& endpoint,
                                                                      const CanFrame& marker) {
  std::vector<TimedCanFrame> received;
  for (int poll = 0; poll < kMaxPolls; ++poll) {
    backend_->Advance(kPollStepNs);
    endpoint.Receive(backend_->NowNs(), received);
    for (std::size_t i = 0; i < received.size(); ++i) {
      if (received[i].frame == marker) {
        received.resize(i);
        return received;
      }
    }
  }
  ADD_FAILURE() << backend_->Name() << ": marker " << marker << " never arrived";
  return received;
}

}  // namespace hilrig::rig
