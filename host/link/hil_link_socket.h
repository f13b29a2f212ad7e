// The HIL link's connection: the length-delimited frames of host/link/hil_link_codec.h over a
// ByteStream transport. Two transports carry it: one TCP connection between the runner and a DUT
// process (the runner listens, on 127.0.0.1 unless told otherwise, so the link is not reachable
// from the network, and the DUT connects), or the shared-memory rings of
// host/link/shm_byte_stream.h for a DUT process the runner started on the same host. Lockstep
// needs blocking calls with a deadline (the runner's watchdog), and real-time pacing needs a poll
// that never blocks; both are here, whatever the transport. TCP sends use MSG_NOSIGNAL, so a peer
// that vanished shows as an error value, never as SIGPIPE.
//
// Threading: one connection is used from one thread at a time.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "host/link/byte_stream.h"
#include "host/link/hil_link_codec.h"
#include "rig/result.h"

namespace hilrig::host {

// What a receive call ended with.
enum class LinkReceiveStatus {
  kMessage,      // `message` holds the next message
  kTimeout,      // nothing complete arrived before the deadline (or, for Poll, nothing waiting)
  kClosed,       // the peer closed the connection (or it was reset)
  kLinkError,    // the decoder refused the bytes; `error` names it (oversized, malformed, ...)
  kSocketError,  // the transport failed (a socket error, a corrupt shared-memory ring)
};

struct LinkReceived {
  LinkReceiveStatus status = LinkReceiveStatus::kTimeout;
  proto::LinkMessage message;
  std::string error;  // for kLinkError ("<name>: <detail>") and kSocketError
  std::optional<LinkErrorKind> link_error;
};

// A receive that did not deliver a message, as a rig::Error with `message`: kTimeout,
// kLinkClosed, kLinkProtocol (with the LinkErrorKind, see LinkErrorKindOf) or kIo.
rig::Error LinkReceiveError(const LinkReceived& received, std::string message);

class LinkConnection {
 public:
  // Connects to host:port, waiting at most timeout_ms for the peer to accept, and less when
  // `stop_requested` (may be null) is set meanwhile (kInterrupted).
  static rig::Result<std::unique_ptr<LinkConnection>> Connect(
      const std::string& host, std::uint16_t port, int timeout_ms,
      const std::atomic<bool>* stop_requested = nullptr);
  // The link over any transport; `peer` names the other end for logs ("127.0.0.1:4711").
  LinkConnection(std::unique_ptr<ByteStream> stream, std::string peer);
  ~LinkConnection();
  LinkConnection(const LinkConnection&) = delete;
  LinkConnection& operator=(const LinkConnection&) = delete;

  // Encodes and writes the whole frame (after any queued ones), waiting at most timeout_ms for
  // the transport to take it.
  rig::Result<void> Send(const proto::LinkMessage& message, int timeout_ms = 1000);
  // Encodes the frame and keeps it for the next Send or Flush, so that a lockstep tick's inputs
  // and its step request go out in one write. Fails only when the message cannot be encoded.
  rig::Result<void> Queue(const proto::LinkMessage& message);
  // Writes the queued frames, if any; fails like Send.
  rig::Result<void> Flush(int timeout_ms = 1000);
  // Writes raw bytes as they are (test hooks that play a broken peer).
  rig::Result<void> SendBytes(const std::string& bytes, int timeout_ms = 1000);
  // The next message, waiting at most timeout_ms (0: do not wait).
  LinkReceived Receive(int timeout_ms);
  LinkReceived Poll() { return Receive(0); }

  // The peer closed the connection (seen by a receive or a send); frames already received may
  // still be waiting in the decoder.
  bool closed() const { return closed_; }
  const LinkCounters& counters() const { return decoder_.counters(); }
  std::uint64_t frames_sent() const { return frames_sent_; }
  const std::string& peer() const { return peer_; }

 private:
  LinkReceived FromDecoder();

  std::unique_ptr<ByteStream> stream_;
  std::string peer_;
  LinkDecoder decoder_;
  bool closed_ = false;
  std::string queued_;  // encoded frames not written yet
  std::uint64_t frames_queued_ = 0;
  std::uint64_t frames_sent_ = 0;
};

class LinkListener {
 public:
  // Listens on address:port; port 0 picks a free one (see port()).
  static rig::Result<std::unique_ptr<LinkListener>> Listen(const std::string& address = "127.0.0.1",
                                                           std::uint16_t port = 0);
  ~LinkListener();
  LinkListener(const LinkListener&) = delete;
  LinkListener& operator=(const LinkListener&) = delete;

  std::uint16_t port() const;
  // The next connection, or an error once timeout_ms passed without one (kTimeout).
  rig::Result<std::unique_ptr<LinkConnection>> Accept(int timeout_ms);
  // The same, as the byte stream under it (for a link of another framing); `peer` names it.
  struct AcceptedStream {
    std::unique_ptr<ByteStream> stream;
    std::string peer;
  };
  rig::Result<AcceptedStream> AcceptStream(int timeout_ms);

 private:
  struct Acceptor;
  explicit LinkListener(std::unique_ptr<Acceptor> acceptor);
  std::unique_ptr<Acceptor> acceptor_;
};

}  // namespace hilrig::host
