#include "host/link/dut_acceptor.h"

#include <algorithm>
#include <utility>

namespace hilrig::host {

const char* PeerRejectionName(PeerRejection reason) {
  switch (reason) {
    case PeerRejection::kClosed:
      return "closed";
    case PeerRejection::kLinkError:
      return "link_error";
    case PeerRejection::kNotAHello:
      return "not_a_hello";
    case PeerRejection::kNotADut:
      return "not_a_dut";
    case PeerRejection::kNoToken:
      return "no_token";
    case PeerRejection::kWrongToken:
      return "wrong_token";
    case PeerRejection::kSilent:
      return "silent";
  }
  return "unknown";
}

DutAcceptor::DutAcceptor(LinkListener& listener, LinkToken token)
    : listener_(listener), token_(token) {}

DutAcceptor::~DutAcceptor() = default;

std::optional<AcceptedDut> DutAcceptor::Poll(int wait_ms) {
  if (auto dut = JudgeAll()) return dut;
  TakeNewConnections();
  if (auto dut = JudgeAll()) return dut;
  if (pending_.empty()) {
    // Nothing to read: wait for a connection (an accept that fails is retried next round).
    auto link = listener_.Accept(wait_ms);
    if (link) Add(std::move(link).value());
    return JudgeAll();
  }
  // Wait on the oldest; the others are read again next round, so a silent one delays the DUT by
  // one round at most.
  std::optional<AcceptedDut> dut = Judge(pending_.front(), pending_.front().link->Receive(wait_ms));
  if (dut) RefusePending();
  Sweep();
  return dut;
}

void DutAcceptor::RefusePending() {
  for (Pending& pending : pending_) {
    if (pending.link) Refuse(pending, PeerRejection::kSilent);
  }
  pending_.clear();
}

std::string DutAcceptor::RejectedSummary() const {
  if (rejected_count_ == 0) return "";
  std::string text = std::to_string(rejected_count_) + " link peer" +
                     (rejected_count_ == 1 ? "" : "s") + " refused: ";
  for (std::size_t i = 0; i < named_rejected_.size(); ++i) {
    text += (i == 0 ? "" : ", ") + named_rejected_[i].address + " (" +
            PeerRejectionName(named_rejected_[i].reason) + ")";
  }
  if (rejected_count_ > named_rejected_.size()) text += ", ...";
  return text;
}

void DutAcceptor::TakeNewConnections() {
  for (std::size_t taken = 0; taken < kMaxPending; ++taken) {
    auto link = listener_.Accept(0);
    if (!link) return;
    Add(std::move(link).value());
  }
}

void DutAcceptor::Add(std::unique_ptr<LinkConnection> link) {
  if (pending_.size() >= kMaxPending) {
    Refuse(pending_.front(), PeerRejection::kSilent);
    pending_.erase(pending_.begin());
  }
  std::string address = link->peer();
  pending_.push_back({std::move(link), std::move(address)});
}

std::optional<AcceptedDut> DutAcceptor::JudgeAll() {
  std::optional<AcceptedDut> dut;
  for (Pending& pending : pending_) {
    dut = Judge(pending, pending.link->Poll());
    if (dut) break;
  }
  if (dut) RefusePending();
  Sweep();
  return dut;
}

std::optional<AcceptedDut> DutAcceptor::Judge(Pending& pending, LinkReceived received) {
  switch (received.status) {
    case LinkReceiveStatus::kTimeout:
      return std::nullopt;
    case LinkReceiveStatus::kClosed:
      Refuse(pending, PeerRejection::kClosed);
      return std::nullopt;
    case LinkReceiveStatus::kLinkError:
    case LinkReceiveStatus::kSocketError:
      Refuse(pending, PeerRejection::kLinkError);
      return std::nullopt;
    case LinkReceiveStatus::kMessage:
      break;
  }
  const proto::LinkMessage& message = received.message;
  if (!message.has_hello()) {
    Refuse(pending, PeerRejection::kNotAHello);
  } else if (message.hello().role() != proto::Hello::DUT) {
    Refuse(pending, PeerRejection::kNotADut);
  } else if (message.hello().token().empty()) {
    Refuse(pending, PeerRejection::kNoToken);
  } else if (!ProvesLinkToken(token_, message.hello().token())) {
    Refuse(pending, PeerRejection::kWrongToken);
  } else {
    return AcceptedDut{std::move(pending.link), message.hello()};
  }
  return std::nullopt;
}

void DutAcceptor::Refuse(Pending& pending, PeerRejection reason) {
  // Best effort and without waiting: a DUT started by hand with the wrong token learns why.
  proto::LinkMessage bye;
  bye.mutable_bye()->set_error(true);
  bye.mutable_bye()->set_reason(std::string("refused: ") + PeerRejectionName(reason));
  LinkSequencer().Stamp(bye, 0);
  (void)pending.link->Send(bye, 0);
  ++rejected_count_;
  if (named_rejected_.size() < kMaxNamed) named_rejected_.push_back({pending.address, reason});
  pending.link.reset();
}

void DutAcceptor::Sweep() {
  std::erase_if(pending_, [](const Pending& pending) { return !pending.link; });
}

}  // namespace hilrig::host
