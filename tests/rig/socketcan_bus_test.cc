// Tests of the SocketCAN backend. The error-frame decoding tests run everywhere. The SocketCan*
// tests need a kernel with AF_CAN and a CAN interface named by HILRIG_SOCKETCAN_IFACE (default
// vcan0); where there is none they skip, and the vm test (tests/vm) runs them under QEMU on a
// Debian kernel with vcan.
#include "rig/socketcan_bus.h"

#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "tests/rig/can_bus_conformance.h"

namespace hilrig::rig {
namespace {

constexpr std::int64_t kWaitSliceNs = 200'000'000;
// Bounds every wait on the kernel: 25 slices of 200 ms. vcan delivers within microseconds, so
// only a broken backend ever reaches the bound.
constexpr int kMaxWaitSlices = 25;

std::string InterfaceUnderTest() {
  const char* name = std::getenv("HILRIG_SOCKETCAN_IFACE");
  return name != nullptr && name[0] != '\0' ? name : "vcan0";
}

bool KernelHasAfCan() {
  const int fd = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd < 0) return errno != EAFNOSUPPORT;
  ::close(fd);
  return true;
}

CanFrame ErrorFrame(std::uint32_t classes, std::array<std::uint8_t, 8> data = {}) {
  return CanFrame::ErrorFrame(classes, data);
}

std::vector<BusEventKind> Kinds(const std::vector<BusEvent>& events) {
  std::vector<BusEventKind> kinds;
  for (const BusEvent& event : events) kinds.push_back(event.kind);
  return kinds;
}

std::vector<std::uint32_t> Ids(const std::vector<TimedCanFrame>& frames) {
  std::vector<std::uint32_t> ids;
  for (const TimedCanFrame& timed : frames) ids.push_back(timed.frame.id);
  return ids;
}

std::string CannotOpenReason(const std::string& interface, const Error& error) {
  if (!KernelHasAfCan()) return "no AF_CAN in this kernel; the vm test runs these under QEMU";
  return "cannot open " + interface + ": " + error.message;
}

// ---- The shared CanBus conformance suite on SocketCAN. ----

// Endpoints are sockets on one interface; the kernel loops each socket's frames back to the
// others, as it does for processes sharing a real bus. Time is only a counter: frames carry the
// kernel's stamps, and Advance yields so the kernel's softirq can deliver.
class SocketCanBackend final : public CanBusBackend {
 public:
  SocketCanBackend() : interface_(InterfaceUnderTest()) {
    Result<std::unique_ptr<SocketCanBus>> probe = OpenSocketCan(interface_);
    if (probe.ok()) {
      supports_fd_ = probe.value()->fd_capable();
    } else {
      skip_reason_ = CannotOpenReason(interface_, probe.error());
    }
  }

  std::string Name() const override { return "socketcan " + interface_; }
  std::optional<std::string> SkipReason() const override { return skip_reason_; }

  Result<std::vector<std::unique_ptr<CanBus>>> MakeEndpoints(std::size_t count) override {
    std::vector<std::unique_ptr<CanBus>> endpoints;
    for (std::size_t k = 0; k < count; ++k) {
      Result<std::unique_ptr<SocketCanBus>> bus = OpenSocketCan(interface_);
      if (!bus.ok()) return bus.error();
      endpoints.push_back(std::move(bus).value());
    }
    return endpoints;
  }

  std::int64_t NowNs() const override { return now_ns_; }
  void Advance(std::int64_t dt_ns) override {
    now_ns_ += dt_ns;
    std::this_thread::yield();
  }
  bool SupportsFd() const override { return supports_fd_; }

 private:
  std::string interface_;
  std::optional<std::string> skip_reason_;
  bool supports_fd_ = false;
  std::int64_t now_ns_ = 0;
};

INSTANTIATE_TEST_SUITE_P(SocketCan, CanBusConformanceTest,
                         ::testing::Values(CanBusBackendParam{
                             "socketcan", [] { return std::make_unique<SocketCanBackend>(); }}),
                         CanBusBackendParamName);

// ---- Error-frame decoding: pure, runs on any kernel. ----

TEST(SocketCanErrorDecodingTest, BusOffFrameIsBusOffEvent) {
  const CanFrame frame = ErrorFrame(CAN_ERR_BUSOFF);

  const std::vector<BusEvent> events = DecodeErrorFrame(frame, 42);

  ASSERT_EQ(Kinds(events), std::vector<BusEventKind>{BusEventKind::kBusOff});
  EXPECT_EQ(events[0].time_ns, 42);
  EXPECT_EQ(events[0].frame, frame);
}

TEST(SocketCanErrorDecodingTest, ControllerStatusGivesPassiveAndWarningPerCounter) {
  std::array<std::uint8_t, 8> data{};
  data[1] = CAN_ERR_CRTL_TX_PASSIVE | CAN_ERR_CRTL_RX_WARNING;

  const std::vector<BusEvent> events = DecodeErrorFrame(ErrorFrame(CAN_ERR_CRTL, data), 0);

  ASSERT_EQ(Kinds(events),
            (std::vector<BusEventKind>{BusEventKind::kErrorPassive, BusEventKind::kErrorWarning}));
  EXPECT_TRUE(events[0].tx);
  EXPECT_FALSE(events[1].tx);
}

TEST(SocketCanErrorDecodingTest, ControllerOverflowsAreOverflowEvents) {
  std::array<std::uint8_t, 8> data{};
  data[1] = CAN_ERR_CRTL_RX_OVERFLOW | CAN_ERR_CRTL_TX_OVERFLOW;

  const std::vector<BusEvent> events = DecodeErrorFrame(ErrorFrame(CAN_ERR_CRTL, data), 0);

  EXPECT_EQ(Kinds(events),
            (std::vector<BusEventKind>{BusEventKind::kRxOverflow, BusEventKind::kTxOverflow}));
}

TEST(SocketCanErrorDecodingTest, AckErrorCarriesErrorCounters) {
  std::array<std::uint8_t, 8> data{};
  data[6] = 136;  // TX error counter
  data[7] = 3;    // RX error counter

  const std::vector<BusEvent> events =
      DecodeErrorFrame(ErrorFrame(CAN_ERR_ACK | CAN_ERR_CNT, data), 0);

  ASSERT_EQ(Kinds(events), std::vector<BusEventKind>{BusEventKind::kAckError});
  EXPECT_TRUE(events[0].has_counters);
  EXPECT_EQ(events[0].tx_error_count, 136);
  EXPECT_EQ(events[0].rx_error_count, 3);
}

TEST(SocketCanErrorDecodingTest, DataFrameYieldsNoEvents) {
  const CanFrame frame = CanFrame::Classic(CAN_ERR_BUSOFF, std::array<std::uint8_t, 1>{0});

  EXPECT_TRUE(DecodeErrorFrame(frame, 0).empty());
}

TEST(SocketCanErrorDecodingTest, StateFollowsBusOffAndRestart) {
  std::array<std::uint8_t, 8> passive{};
  passive[1] = CAN_ERR_CRTL_TX_PASSIVE;
  BusState state = BusState::kErrorActive;

  std::vector<BusState> states;
  for (const CanFrame& frame : {ErrorFrame(CAN_ERR_CRTL, passive), ErrorFrame(CAN_ERR_BUSOFF),
                                ErrorFrame(CAN_ERR_RESTARTED)}) {
    for (const BusEvent& event : DecodeErrorFrame(frame, 0)) state = NextBusState(state, event);
    states.push_back(state);
  }

  EXPECT_EQ(states, (std::vector<BusState>{BusState::kErrorPassive, BusState::kBusOff,
                                           BusState::kErrorActive}));
}

TEST(SocketCanErrorDecodingTest, PassiveOnOneCounterWinsOverWarningOnTheOther) {
  std::array<std::uint8_t, 8> data{};
  data[1] = CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_WARNING;
  BusState state = BusState::kErrorActive;

  for (const BusEvent& event : DecodeErrorFrame(ErrorFrame(CAN_ERR_CRTL, data), 0)) {
    state = NextBusState(state, event);
  }

  EXPECT_EQ(state, BusState::kErrorPassive);
}

// ---- The ENOBUFS retry, with a scripted send: runs on any kernel. ----

struct ScriptedSend {
  explicit ScriptedSend(std::vector<int> results_in) : results(std::move(results_in)) {}

  std::vector<int> results;  // errno per attempt; past the end, every attempt fails with the last
  std::size_t attempts = 0;
  std::vector<std::int64_t> pauses_ns;

  SendRetryOutcome Run(int max_retries) {
    return SendWithRetry([this] { return results[std::min(attempts++, results.size() - 1)]; },
                         max_retries, 100,
                         [this](std::int64_t pause_ns) { pauses_ns.push_back(pause_ns); });
  }
};

TEST(SocketCanSendRetryTest, FullQueueIsRetriedUntilItDrains) {
  ScriptedSend send({ENOBUFS, ENOBUFS, EAGAIN, 0});

  const SendRetryOutcome outcome = send.Run(8);

  EXPECT_EQ(outcome.error_number, 0);
  EXPECT_EQ(outcome.retries, 3);
  EXPECT_EQ(send.pauses_ns, (std::vector<std::int64_t>{100, 200, 400}));
}

TEST(SocketCanSendRetryTest, QueueThatStaysFullFailsAfterTheBound) {
  ScriptedSend send({ENOBUFS});

  const SendRetryOutcome outcome = send.Run(4);

  EXPECT_EQ(outcome.error_number, ENOBUFS);
  EXPECT_EQ(outcome.retries, 4);
  EXPECT_EQ(send.attempts, 5u);
}

TEST(SocketCanSendRetryTest, OtherErrorsAreNotRetried) {
  ScriptedSend send({ENETDOWN, 0});

  const SendRetryOutcome outcome = send.Run(8);

  EXPECT_EQ(outcome.error_number, ENETDOWN);
  EXPECT_EQ(outcome.retries, 0);
  EXPECT_TRUE(send.pauses_ns.empty());
}

TEST(SocketCanSendRetryTest, InterruptedSendIsRepeatedWithoutCounting) {
  ScriptedSend send({EINTR, 0});

  const SendRetryOutcome outcome = send.Run(0);

  EXPECT_EQ(outcome.error_number, 0);
  EXPECT_EQ(outcome.retries, 0);
}

TEST(SocketCanOpenTest, MissingAfCanIsAnErrorValueNotACrash) {
  if (KernelHasAfCan()) GTEST_SKIP() << "this kernel has AF_CAN; nothing to check here";

  const Result<std::unique_ptr<SocketCanBus>> bus = OpenSocketCan("vcan0");

  ASSERT_FALSE(bus.ok());
  EXPECT_NE(bus.error().message.find("no AF_CAN"), std::string::npos) << bus.error().message;
}

// ---- Against a real kernel interface. ----

class SocketCanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    interface_ = InterfaceUnderTest();
    Result<std::unique_ptr<SocketCanBus>> probe = OpenSocketCan(interface_);
    if (!probe.ok()) {
      GTEST_SKIP() << (KernelHasAfCan() ? "cannot open " + interface_ + ": " + probe.error().message
                                        : std::string("no AF_CAN in this kernel; the vm test "
                                                      "runs these under QEMU"));
    }
  }

  std::unique_ptr<SocketCanBus> Open(const SocketCanOptions& options = {}) {
    Result<std::unique_ptr<SocketCanBus>> bus = OpenSocketCan(interface_, options);
    EXPECT_TRUE(bus.ok()) << bus.error().message;
    return std::move(bus).value();
  }

  // Bounded: waits for `count` frames or gives up after kMaxWaitSlices quiet slices.
  static std::vector<TimedCanFrame> ReceiveAtLeast(SocketCanBus& bus, std::size_t count) {
    std::vector<TimedCanFrame> out;
    for (int slice = 0; slice < kMaxWaitSlices && out.size() < count; ++slice) {
      bus.Receive(0, out);
      if (out.size() < count) bus.WaitReadable(kWaitSliceNs);
    }
    bus.Receive(0, out);
    return out;
  }

  // A frame sent after `frames` marks the end of the traffic, so the test knows that everything
  // sent before it has had its chance to arrive, without waiting for an absence.
  void SendWithMarker(SocketCanBus& sender, const std::vector<CanFrame>& frames) {
    for (const CanFrame& frame : frames) ASSERT_TRUE(sender.Send(frame, 0).ok());
    ASSERT_TRUE(sender.Send(Marker(), 0).ok());
  }
  static CanFrame Marker() {
    return CanFrame::ClassicExtended(kMarkerId, std::array<std::uint8_t, 1>{0xEE});
  }
  static std::vector<TimedCanFrame> ReceiveUntilMarker(SocketCanBus& bus) {
    std::vector<TimedCanFrame> out;
    for (int slice = 0; slice < kMaxWaitSlices; ++slice) {
      bus.Receive(0, out);
      for (std::size_t i = 0; i < out.size(); ++i) {
        if (out[i].frame == Marker()) {
          out.erase(out.begin() + static_cast<std::ptrdiff_t>(i));
          return out;
        }
      }
      bus.WaitReadable(kWaitSliceNs);
    }
    ADD_FAILURE() << "marker frame never arrived";
    return out;
  }

  static constexpr std::uint32_t kMarkerId = 0x1FFFFFF0;
  // Lets the marker through filters under test without matching what they test.
  static CanFilter MarkerFilter() {
    CanFilter filter;
    filter.id = kMarkerId;
    filter.mask = kMaxExtendedId;
    filter.extended = true;
    return filter;
  }

  std::string interface_;
};

TEST_F(SocketCanTest, FramesCarryKernelReceiveTimes) {
  auto sender = Open();
  auto receiver = Open();

  for (std::uint32_t id = 1; id <= 5; ++id) {
    ASSERT_TRUE(sender->Send(CanFrame::Classic(id, std::array<std::uint8_t, 1>{0}), 0).ok());
  }
  const std::vector<TimedCanFrame> received = ReceiveAtLeast(*receiver, 5);

  ASSERT_EQ(received.size(), 5u);
  // Receive was passed now_ns = 0, so these stamps come from the kernel: epoch time, after 2001.
  EXPECT_GT(received[0].time_ns, 1'000'000'000'000'000'000);
  for (std::size_t i = 1; i < received.size(); ++i) {
    EXPECT_GE(received[i].time_ns, received[i - 1].time_ns);
  }
}

TEST_F(SocketCanTest, StandardFilterPassesOnlyMatchingIds) {
  auto sender = Open();
  SocketCanOptions options;
  CanFilter sample_ids;
  sample_ids.id = 0x100;
  sample_ids.mask = 0x7F0;
  options.filters = {sample_ids, MarkerFilter()};
  auto receiver = Open(options);

  SendWithMarker(*sender, {CanFrame::Classic(0x105, {}), CanFrame::Classic(0x205, {}),
                           CanFrame::ClassicExtended(0x105, {}), CanFrame::Classic(0x10F, {})});

  EXPECT_EQ(Ids(ReceiveUntilMarker(*receiver)), (std::vector<std::uint32_t>{0x105, 0x10F}));
}

// vcan has no controller, but it carries error frames sent into it, which is how a bench rig
// injects faults; the receiving socket decodes them like a real controller's.
TEST_F(SocketCanTest, InjectedBusOffIsDecodedAndDeliveredWhenAsked) {
  auto injector = Open();
  SocketCanOptions options;
  options.error_frame_mask = kCanErrMask;
  auto wants_errors = Open(options);

  ASSERT_TRUE(injector->Send(ErrorFrame(CAN_ERR_BUSOFF), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveAtLeast(*wants_errors, 1);

  ASSERT_EQ(received.size(), 1u);
  EXPECT_TRUE(received[0].frame.error);
  EXPECT_EQ(Kinds(wants_errors->TakeEvents()), std::vector<BusEventKind>{BusEventKind::kBusOff});
  EXPECT_EQ(wants_errors->state(), BusState::kBusOff);
  EXPECT_FALSE(wants_errors->Send(CanFrame::Classic(0x1, {}), 0).ok());
}

TEST_F(SocketCanTest, StateIsTrackedEvenWithoutErrorFramesRequested) {
  auto injector = Open();
  auto receiver = Open();
  std::array<std::uint8_t, 8> passive{};
  passive[1] = CAN_ERR_CRTL_RX_PASSIVE;

  ASSERT_TRUE(injector->Send(ErrorFrame(CAN_ERR_CRTL, passive), 0).ok());
  SendWithMarker(*injector, {});
  const std::vector<TimedCanFrame> received = ReceiveUntilMarker(*receiver);

  EXPECT_TRUE(received.empty());
  EXPECT_EQ(receiver->state(), BusState::kErrorPassive);
  EXPECT_EQ(Kinds(receiver->TakeEvents()), std::vector<BusEventKind>{BusEventKind::kErrorPassive});
}

TEST_F(SocketCanTest, AckErrorsArriveOnlyWhenErrorFramesRequested) {
  auto injector = Open();
  auto quiet = Open();
  auto wants_errors = Open();
  wants_errors->SetReceiveErrorFrames(true);

  ASSERT_TRUE(injector->Send(ErrorFrame(CAN_ERR_ACK), 0).ok());
  SendWithMarker(*injector, {});
  ReceiveUntilMarker(*quiet);
  ReceiveUntilMarker(*wants_errors);

  EXPECT_TRUE(quiet->TakeEvents().empty());
  EXPECT_EQ(Kinds(wants_errors->TakeEvents()), std::vector<BusEventKind>{BusEventKind::kAckError});
}

TEST_F(SocketCanTest, UndrainedSocketReportsKernelDrops) {
  auto sender = Open();
  SocketCanOptions options;
  options.receive_buffer_bytes = 1;  // the kernel's minimum: a handful of frames
  auto receiver = Open(options);
  constexpr int kFrames = 2000;

  for (int i = 0; i < kFrames; ++i) {
    ASSERT_TRUE(sender->Send(CanFrame::Classic(0x10, std::array<std::uint8_t, 8>{}), 0).ok());
  }
  // The kernel reports its drop count with the next frame it does queue for the socket, so keep
  // draining and sending one more frame until the count shows up.
  std::vector<TimedCanFrame> received;
  for (int slice = 0;
       slice < kMaxWaitSlices && receiver->counters().frames_dropped_rx_overflow == 0; ++slice) {
    receiver->Receive(0, received);
    ASSERT_TRUE(sender->Send(Marker(), 0).ok());
    receiver->WaitReadable(kWaitSliceNs);
    receiver->Receive(0, received);
  }

  EXPECT_GT(receiver->counters().frames_dropped_rx_overflow, 0u);
  EXPECT_LT(received.size(), static_cast<std::size_t>(kFrames));
  const std::vector<BusEvent> events = receiver->TakeEvents();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0].kind, BusEventKind::kSocketOverflow);
  EXPECT_EQ(events[0].dropped_frames, receiver->counters().frames_dropped_rx_overflow);
}

TEST_F(SocketCanTest, WaitReadableReturnsOnceAFrameIsQueued) {
  auto sender = Open();
  auto receiver = Open();

  const bool readable_before = receiver->WaitReadable(0);
  ASSERT_TRUE(sender->Send(CanFrame::Classic(0x5, {}), 0).ok());
  const bool readable_after = receiver->WaitReadable(5'000'000'000);

  EXPECT_FALSE(readable_before);
  EXPECT_TRUE(readable_after);
}

TEST_F(SocketCanTest, InvalidFrameIsRefusedAsAValue) {
  auto bus = Open();
  CanFrame frame = CanFrame::Classic(0x1, {});
  frame.id = 0x800;  // does not fit 11 bits

  const Result<void> sent = bus->Send(frame, 0);

  EXPECT_FALSE(sent.ok());
  EXPECT_EQ(bus->counters().send_failures, 1u);
}

TEST_F(SocketCanTest, UnknownInterfaceIsAnErrorValue) {
  const Result<std::unique_ptr<SocketCanBus>> bus = OpenSocketCan("nosuchcan9");

  ASSERT_FALSE(bus.ok());
  EXPECT_NE(bus.error().message.find("nosuchcan9"), std::string::npos) << bus.error().message;
}

// Needs a second interface with the classic MTU (the vm test makes one: ip link set mtu 16).
TEST_F(SocketCanTest, FdFrameOnClassicInterfaceIsRefused) {
  const char* classic = std::getenv("HILRIG_SOCKETCAN_CLASSIC_IFACE");
  if (classic == nullptr || classic[0] == '\0') {
    GTEST_SKIP() << "set HILRIG_SOCKETCAN_CLASSIC_IFACE to a CAN interface with MTU 16";
  }
  Result<std::unique_ptr<SocketCanBus>> bus = OpenSocketCan(classic);
  ASSERT_TRUE(bus.ok()) << bus.error().message;

  const Result<void> sent =
      bus.value()->Send(CanFrame::Fd(0x1, std::array<std::uint8_t, 12>{}, false), 0);

  EXPECT_FALSE(bus.value()->fd_capable());
  ASSERT_FALSE(sent.ok());
  EXPECT_NE(sent.error().message.find("classic MTU"), std::string::npos) << sent.error().message;
}

}  // namespace
}  // namespace hilrig::rig
