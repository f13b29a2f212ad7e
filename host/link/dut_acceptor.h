// The runner's half of the link's authentication: of the connections that reach the runner's link
// port, the DUT is the one whose first message is a DUT hello carrying the link token the runner
// handed its child (host/link/link_token.h). Any process on the host can connect to a loopback
// port, and may do so before the DUT does, so every other connection is refused -- it gets a bye
// saying why, is closed, counted and its address kept for the report -- and none of them stops
// the DUT from connecting: the acceptor keeps accepting, and reads every pending connection each
// round, until the DUT proves itself. The check lives in the handshake, not in the transport, so
// it holds for whatever carries the link.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/link/hil_link_socket.h"
#include "host/link/link_token.h"
#include "rig/result.h"

namespace hilrig::host {

// Why a connection was not taken for the DUT.
enum class PeerRejection {
  kClosed,      // closed before saying anything
  kLinkError,   // sent bytes that are no link message (or of another protocol version)
  kNotAHello,   // its first message was something else
  kNotADut,     // a hello with another role
  kNoToken,     // a DUT hello without a token
  kWrongToken,  // a DUT hello with a token that is not this run's
  kSilent,      // still silent when the DUT proved itself, or pushed out by newer connections
};

// "closed", "link_error", "not_a_hello", "not_a_dut", "no_token", "wrong_token", "silent".
const char* PeerRejectionName(PeerRejection reason);

struct RejectedPeer {
  std::string address;  // as the transport names it, e.g. "127.0.0.1:40312"
  PeerRejection reason = PeerRejection::kClosed;
};

struct AcceptedDut {
  std::unique_ptr<LinkConnection> link;
  proto::Hello hello;
};

class DutAcceptor {
 public:
  // Connections waiting for their first message at once; a newer one pushes out the oldest.
  static constexpr std::size_t kMaxPending = 16;
  // Rejected peers whose address is kept (all of them are counted).
  static constexpr std::size_t kMaxNamed = 4;

  // `listener` must outlive the acceptor.
  DutAcceptor(LinkListener& listener, LinkToken token);
  ~DutAcceptor();
  DutAcceptor(const DutAcceptor&) = delete;
  DutAcceptor& operator=(const DutAcceptor&) = delete;

  // One round: takes the connections waiting on the listener and judges what each has sent,
  // waiting at most wait_ms for something to happen. Returns the DUT once a connection proved the
  // token (the others still pending are then refused as silent); nullopt until then.
  std::optional<AcceptedDut> Poll(int wait_ms);

  // Refuses every connection still pending (as silent): for a start that gives up, so that the
  // summary counts them.
  void RefusePending();

  std::uint64_t rejected_count() const { return rejected_count_; }
  const std::vector<RejectedPeer>& named_rejected() const { return named_rejected_; }
  // "" with none; else e.g. "2 link peers refused: 127.0.0.1:40312 (no_token), ...".
  std::string RejectedSummary() const;

 private:
  struct Pending {
    std::unique_ptr<LinkConnection> link;
    std::string address;
  };

  void TakeNewConnections();
  void Add(std::unique_ptr<LinkConnection> link);
  // The DUT if `received` proves the token; otherwise refuses the connection unless it has yet to
  // say anything (then it stays pending). Either way `pending` is left for Sweep.
  std::optional<AcceptedDut> Judge(Pending& pending, LinkReceived received);
  void Refuse(Pending& pending, PeerRejection reason);
  std::optional<AcceptedDut> JudgeAll();
  void Sweep();  // drops the refused entries

  LinkListener& listener_;
  LinkToken token_;
  std::vector<Pending> pending_;  // oldest first; a refused one has a null link until swept
  std::uint64_t rejected_count_ = 0;
  std::vector<RejectedPeer> named_rejected_;
};

}  // namespace hilrig::host
