// The runner's authentication of the DUT on real loopback sockets, the test playing the DUT and
// the intruders. Every wait is bounded.
#include "host/link/dut_acceptor.h"

#include <gtest/gtest.h>

#include <vector>

namespace hilrig::host {
namespace {

constexpr int kWaitMs = 2000;
constexpr int kMaxRounds = 200;  // Poll rounds of up to kRoundMs each
constexpr int kRoundMs = 20;

class DutAcceptorTest : public ::testing::Test {
 protected:
  std::unique_ptr<LinkConnection> Connect() {
    return LinkConnection::Connect("127.0.0.1", listener_->port(), kWaitMs).value();
  }

  static proto::LinkMessage Hello(proto::Hello::Role role, const std::string& proof) {
    proto::LinkMessage hello;
    hello.mutable_hello()->set_role(role);
    hello.mutable_hello()->set_token(proof);
    LinkSequencer().Stamp(hello, 0);
    return hello;
  }

  // Polls until the DUT is accepted or the rounds run out.
  std::optional<AcceptedDut> AcceptDut() {
    for (int round = 0; round < kMaxRounds; ++round) {
      if (auto dut = acceptor_.Poll(kRoundMs)) return dut;
    }
    return std::nullopt;
  }

  // What a refused peer hears before its connection is closed.
  static std::string ByeReason(LinkConnection& peer) {
    const LinkReceived received = peer.Receive(kWaitMs);
    return received.status == LinkReceiveStatus::kMessage ? received.message.bye().reason() : "";
  }

  std::unique_ptr<LinkListener> listener_ = LinkListener::Listen().value();
  LinkToken token_ = NewLinkToken().value();
  DutAcceptor acceptor_{*listener_, token_};
};

TEST_F(DutAcceptorTest, TheDutThatProvesTheTokenIsAccepted) {
  auto dut = Connect();
  ASSERT_TRUE(dut->Send(Hello(proto::Hello::DUT, token_.Proof())).ok());
  const auto accepted = AcceptDut();
  ASSERT_TRUE(accepted.has_value());
  EXPECT_EQ(accepted->hello.role(), proto::Hello::DUT);
  EXPECT_EQ(acceptor_.rejected_count(), 0u);
  EXPECT_EQ(acceptor_.RejectedSummary(), "");
}

TEST_F(DutAcceptorTest, PeersThatConnectFirstAreRefusedNamedAndCounted) {
  auto no_token = Connect();
  ASSERT_TRUE(no_token->Send(Hello(proto::Hello::DUT, "")).ok());
  auto wrong_token = Connect();
  ASSERT_TRUE(wrong_token->Send(Hello(proto::Hello::DUT, std::string(16, 'x'))).ok());
  auto runner = Connect();
  ASSERT_TRUE(runner->Send(Hello(proto::Hello::RUNNER, token_.Proof())).ok());
  auto garbage = Connect();
  ASSERT_TRUE(garbage->SendBytes(std::string("\x04\x0f\xff\xff\xff", 5)).ok());
  auto dut = Connect();
  ASSERT_TRUE(dut->Send(Hello(proto::Hello::DUT, token_.Proof())).ok());

  const auto accepted = AcceptDut();

  ASSERT_TRUE(accepted.has_value());
  EXPECT_EQ(acceptor_.rejected_count(), 4u);
  std::vector<PeerRejection> reasons;
  for (const RejectedPeer& peer : acceptor_.named_rejected()) reasons.push_back(peer.reason);
  EXPECT_EQ(reasons,
            (std::vector<PeerRejection>{PeerRejection::kNoToken, PeerRejection::kWrongToken,
                                        PeerRejection::kNotADut, PeerRejection::kLinkError}));
  EXPECT_EQ(acceptor_.named_rejected()[0].address.rfind("127.0.0.1:", 0), 0u);
  EXPECT_EQ(ByeReason(*no_token), "refused: no_token");
  EXPECT_EQ(ByeReason(*wrong_token), "refused: wrong_token");
  EXPECT_NE(acceptor_.RejectedSummary().find("4 link peers refused: 127.0.0.1:"), std::string::npos)
      << acceptor_.RejectedSummary();
  // The accepted link carries on: the DUT hears the runner.
  proto::LinkMessage step;
  step.mutable_step()->set_tick(1);
  LinkSequencer().Stamp(step, 0);
  ASSERT_TRUE(accepted->link->Send(step).ok());
  const LinkReceived heard = dut->Receive(kWaitMs);
  ASSERT_EQ(heard.status, LinkReceiveStatus::kMessage);
  EXPECT_EQ(heard.message.step().tick(), 1u);
}

TEST_F(DutAcceptorTest, SilentPeerDoesNotKeepTheDutOutAndIsRefusedOnceTheDutIsIn) {
  auto silent = Connect();
  auto dut = Connect();
  ASSERT_TRUE(dut->Send(Hello(proto::Hello::DUT, token_.Proof())).ok());
  ASSERT_TRUE(AcceptDut().has_value());
  EXPECT_EQ(acceptor_.rejected_count(), 1u);
  EXPECT_EQ(acceptor_.named_rejected().at(0).reason, PeerRejection::kSilent);
  EXPECT_EQ(ByeReason(*silent), "refused: silent");
}

TEST_F(DutAcceptorTest, FloodOfSilentPeersDoesNotKeepTheDutOut) {
  std::vector<std::unique_ptr<LinkConnection>> flood;
  for (std::size_t i = 0; i < 3 * DutAcceptor::kMaxPending; ++i) {
    flood.push_back(Connect());
    (void)acceptor_.Poll(0);
  }
  auto dut = Connect();
  ASSERT_TRUE(dut->Send(Hello(proto::Hello::DUT, token_.Proof())).ok());
  ASSERT_TRUE(AcceptDut().has_value());
  EXPECT_EQ(acceptor_.rejected_count(), flood.size());
  EXPECT_EQ(acceptor_.named_rejected().size(), DutAcceptor::kMaxNamed);
  EXPECT_NE(acceptor_.RejectedSummary().find(", ..."), std::string::npos);
}

TEST_F(DutAcceptorTest, NothingIsAcceptedWithoutTheToken) {
  auto peer = Connect();
  ASSERT_TRUE(peer->Send(Hello(proto::Hello::DUT, "")).ok());
  auto silent = Connect();
  for (int round = 0; round < 10; ++round) EXPECT_FALSE(acceptor_.Poll(kRoundMs).has_value());
  acceptor_.RefusePending();
  EXPECT_EQ(acceptor_.rejected_count(), 2u);
  EXPECT_EQ(acceptor_.named_rejected().at(1).reason, PeerRejection::kSilent);
}

}  // namespace
}  // namespace hilrig::host
