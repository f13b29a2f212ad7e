// Integration tests on real loopback sockets: every wait is bounded by a short deadline.
#include "host/link/hil_link_socket.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "tests/support/full_listener.h"

namespace hilrig::host {
namespace {

constexpr int kWaitMs = 2000;  // generous bound for loopback; tests return as soon as data flows

struct Pair {
  std::unique_ptr<LinkConnection> runner;
  std::unique_ptr<LinkConnection> dut;
};

Pair Connected() {
  auto listener = LinkListener::Listen().value();
  Pair pair;
  pair.dut = LinkConnection::Connect("127.0.0.1", listener->port(), kWaitMs).value();
  pair.runner = listener->Accept(kWaitMs).value();
  return pair;
}

proto::LinkMessage Bye(std::uint64_t sequence, const std::string& reason) {
  proto::LinkMessage message;
  message.mutable_bye()->mutable_header()->set_protocol_version(kHilLinkProtocolVersion);
  message.mutable_bye()->mutable_header()->set_sequence(sequence);
  message.mutable_bye()->set_reason(reason);
  return message;
}

TEST(HilLinkSocketTest, MessagesArriveInOrder) {
  Pair pair = Connected();
  ASSERT_TRUE(pair.dut->Send(ToLink(ImuMessage{{0, 1}, {1, 2, 3}, {4, 5, 6}})).ok());
  ASSERT_TRUE(pair.dut->Send(Bye(0, "done")).ok());
  const LinkReceived first = pair.runner->Receive(kWaitMs);
  ASSERT_EQ(first.status, LinkReceiveStatus::kMessage);
  EXPECT_EQ(first.message.imu().gyro_rad_s().z(), 3.0);
  const LinkReceived second = pair.runner->Receive(kWaitMs);
  ASSERT_EQ(second.status, LinkReceiveStatus::kMessage);
  EXPECT_EQ(second.message.bye().reason(), "done");
  EXPECT_EQ(pair.runner->counters().messages, 2u);
  EXPECT_EQ(pair.dut->frames_sent(), 2u);
}

TEST(HilLinkSocketTest, ReceiveTimesOutWhenThePeerIsSilent) {
  Pair pair = Connected();
  EXPECT_EQ(pair.runner->Receive(20).status, LinkReceiveStatus::kTimeout);
}

TEST(HilLinkSocketTest, PollDoesNotWait) {
  Pair pair = Connected();
  EXPECT_EQ(pair.runner->Poll().status, LinkReceiveStatus::kTimeout);
}

TEST(HilLinkSocketTest, ClosedPeerIsReportedAsClosed) {
  Pair pair = Connected();
  pair.dut.reset();
  EXPECT_EQ(pair.runner->Receive(kWaitMs).status, LinkReceiveStatus::kClosed);
}

TEST(HilLinkSocketTest, ClosedIsKnownOnceAReceiveSawTheClose) {
  Pair pair = Connected();
  EXPECT_FALSE(pair.runner->closed());
  pair.dut.reset();
  ASSERT_EQ(pair.runner->Receive(kWaitMs).status, LinkReceiveStatus::kClosed);
  EXPECT_TRUE(pair.runner->closed());
}

TEST(HilLinkSocketTest, MessagesSentBeforeTheCloseAreStillDelivered) {
  Pair pair = Connected();
  ASSERT_TRUE(pair.dut->Send(Bye(0, "last words")).ok());
  pair.dut.reset();
  const LinkReceived last = pair.runner->Receive(kWaitMs);
  ASSERT_EQ(last.status, LinkReceiveStatus::kMessage);
  EXPECT_EQ(last.message.bye().reason(), "last words");
  EXPECT_EQ(pair.runner->Receive(kWaitMs).status, LinkReceiveStatus::kClosed);
}

TEST(HilLinkSocketTest, SendingToAVanishedPeerIsAnErrorNotASignal) {
  Pair pair = Connected();
  pair.dut.reset();
  // The first send may still be accepted by the kernel; a reset follows, and then a send fails.
  bool failed = false;
  for (int i = 0; i < 50 && !failed; ++i) {
    const rig::Result<void> sent = pair.runner->Send(Bye(static_cast<std::uint64_t>(i), "anyone?"));
    failed = !sent.ok();
    if (failed) {
      EXPECT_EQ(sent.error().code, rig::ErrorCode::kLinkClosed) << sent.error().message;
    } else {
      (void)pair.runner->Receive(10);
    }
  }
  EXPECT_TRUE(failed);
}

TEST(HilLinkSocketTest, GarbageFromThePeerIsANamedLinkError) {
  Pair pair = Connected();
  ASSERT_TRUE(pair.dut->SendBytes(std::string("\x04\x0f\xff\xff\xff", 5)).ok());
  const LinkReceived received = pair.runner->Receive(kWaitMs);
  ASSERT_EQ(received.status, LinkReceiveStatus::kLinkError);
  ASSERT_TRUE(received.link_error.has_value());
  EXPECT_EQ(*received.link_error, LinkErrorKind::kMalformed);
  EXPECT_EQ(received.error.rfind("malformed", 0), 0u);
  EXPECT_EQ(pair.runner->counters().malformed, 1u);
  const rig::Error error = LinkReceiveError(received, "bad message (" + received.error + ")");
  EXPECT_EQ(error.code, rig::ErrorCode::kLinkProtocol);
  EXPECT_EQ(LinkErrorKindOf(error), LinkErrorKind::kMalformed);
  EXPECT_EQ(error.message, "bad message (" + received.error + ")");
}

TEST(HilLinkSocketTest, AReceiveThatDeliveredNothingIsAnErrorOfItsCode) {
  Pair pair = Connected();
  const LinkReceived silent = pair.runner->Receive(0);
  ASSERT_EQ(silent.status, LinkReceiveStatus::kTimeout);
  EXPECT_EQ(LinkReceiveError(silent, "no answer").code, rig::ErrorCode::kTimeout);
  pair.dut.reset();
  const LinkReceived closed = pair.runner->Receive(kWaitMs);
  ASSERT_EQ(closed.status, LinkReceiveStatus::kClosed);
  EXPECT_EQ(LinkReceiveError(closed, "gone").code, rig::ErrorCode::kLinkClosed);
}

TEST(HilLinkSocketTest, AcceptTimesOutWithoutAPeer) {
  auto listener = LinkListener::Listen().value();
  const auto accepted = listener->Accept(20);
  ASSERT_FALSE(accepted.ok());
  EXPECT_NE(accepted.error().message.find("no connection"), std::string::npos);
  EXPECT_EQ(accepted.error().code, rig::ErrorCode::kTimeout);
}

TEST(HilLinkSocketTest, ConnectToAClosedPortFails) {
  std::uint16_t port = 0;
  {
    auto listener = LinkListener::Listen().value();
    port = listener->port();
  }
  EXPECT_FALSE(LinkConnection::Connect("127.0.0.1", port, kWaitMs).ok());
}

// A connect to a peer that does not answer ends at its timeout, not after the kernel's two minutes
// of SYN retries, and sooner on a stop request: dut_emu's Ctrl-C does not wait out the timeout.
TEST(HilLinkSocketTest, APendingConnectEndsAtItsTimeoutOrAStopRequest) {
  FullListener full;
  const auto pending = LinkConnection::Connect("127.0.0.1", full.port(), 100);
  ASSERT_FALSE(pending.ok()) << "the accept queue did not fill: the connect was answered";
  EXPECT_EQ(pending.error().code, rig::ErrorCode::kTimeout) << pending.error().message;
  std::atomic<bool> stop{false};
  std::thread stopper([&stop] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    stop = true;
  });
  const auto started = std::chrono::steady_clock::now();
  const auto stopped = LinkConnection::Connect("127.0.0.1", full.port(), 60'000, &stop);
  const auto waited = std::chrono::steady_clock::now() - started;
  stopper.join();
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.error().code, rig::ErrorCode::kInterrupted) << stopped.error().message;
  EXPECT_NE(stopped.error().message.find("stopped"), std::string::npos);
  EXPECT_LT(waited, std::chrono::seconds(10));  // a minute without the stop
}

TEST(HilLinkSocketTest, BadAddressIsRefused) {
  EXPECT_FALSE(LinkListener::Listen("not-an-address").ok());
}

}  // namespace
}  // namespace hilrig::host
