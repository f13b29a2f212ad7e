#include "host/link/hil_link_socket.h"

#include <poll.h>
#include <sys/socket.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>

#include "host/link/fd_byte_stream.h"
#include "host/link/poll_wait.h"
#include "host/link/tcp_connect.h"

namespace hilrig::host {
namespace {

namespace asio = boost::asio;
using asio::ip::tcp;

// Connections the kernel holds for accepting: others on the host may connect before the DUT (the
// handshake refuses them), and a full queue would make the DUT's connect wait on a SYN retry.
constexpr int kListenBacklog = 64;

std::string ErrnoText(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

struct TcpSocket {
  asio::io_context io;
  tcp::socket socket{io};
};

// The connected, non-blocking socket as the link's transport.
std::unique_ptr<ByteStream> TcpStream(std::shared_ptr<TcpSocket> socket, const std::string& name) {
  const int fd = socket->socket.native_handle();
  return std::make_unique<FdByteStream>(fd, /*socket=*/true, name, std::move(socket));
}

}  // namespace

struct LinkListener::Acceptor {
  asio::io_context io;
  tcp::acceptor acceptor{io};
};

LinkConnection::LinkConnection(std::unique_ptr<ByteStream> stream, std::string peer)
    : stream_(std::move(stream)), peer_(std::move(peer)) {}
LinkConnection::~LinkConnection() = default;

rig::Result<std::unique_ptr<LinkConnection>> LinkConnection::Connect(
    const std::string& host, std::uint16_t port, int timeout_ms,
    const std::atomic<bool>* stop_requested) {
  auto socket = std::make_shared<TcpSocket>();
  if (auto connected =
          ConnectWithin(socket->socket, host, port, timeout_ms, "link connect", stop_requested);
      !connected) {
    return connected.error();
  }
  return std::make_unique<LinkConnection>(TcpStream(std::move(socket), "link"),
                                          host + ":" + std::to_string(port));
}

rig::Result<void> LinkConnection::Queue(const proto::LinkMessage& message) {
  auto frame = EncodeLinkFrame(message);
  if (!frame) return frame.error();
  queued_ += frame.value();
  ++frames_queued_;
  return {};
}

rig::Result<void> LinkConnection::Flush(int timeout_ms) {
  if (queued_.empty()) return {};
  auto sent = SendBytes(queued_, timeout_ms);
  queued_.clear();
  if (sent) frames_sent_ += frames_queued_;
  frames_queued_ = 0;
  return sent;
}

rig::Result<void> LinkConnection::Send(const proto::LinkMessage& message, int timeout_ms) {
  if (auto queued = Queue(message); !queued) return queued.error();
  return Flush(timeout_ms);
}

rig::Result<void> LinkConnection::SendBytes(const std::string& bytes, int timeout_ms) {
  if (closed_) return rig::MakeError(rig::ErrorCode::kLinkClosed, "link closed by the peer");
  auto sent = stream_->WriteAll(
      std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), timeout_ms);
  if (!sent && sent.error().code == rig::ErrorCode::kLinkClosed) closed_ = true;
  return sent;
}

rig::Error LinkReceiveError(const LinkReceived& received, std::string message) {
  switch (received.status) {
    case LinkReceiveStatus::kLinkError:
      return LinkProtocolError(received.link_error.value_or(LinkErrorKind::kMalformed),
                               std::move(message));
    case LinkReceiveStatus::kClosed:
      return rig::MakeError(rig::ErrorCode::kLinkClosed, std::move(message));
    case LinkReceiveStatus::kTimeout:
      return rig::MakeError(rig::ErrorCode::kTimeout, std::move(message));
    case LinkReceiveStatus::kSocketError:
      return rig::MakeError(rig::ErrorCode::kIo, std::move(message));
    case LinkReceiveStatus::kMessage:
      break;
  }
  return rig::MakeError(std::move(message));
}

LinkReceived LinkConnection::FromDecoder() {
  LinkReceived received;
  std::optional<LinkEvent> event = decoder_.Next();
  if (!event) return received;  // kTimeout: nothing complete yet
  if (auto* message = std::get_if<proto::LinkMessage>(&*event)) {
    received.status = LinkReceiveStatus::kMessage;
    received.message = std::move(*message);
    return received;
  }
  const LinkError& error = std::get<LinkError>(*event);
  received.status = LinkReceiveStatus::kLinkError;
  received.error = error.Message();
  received.link_error = error.kind;
  return received;
}

LinkReceived LinkConnection::Receive(int timeout_ms) {
  const Deadline deadline = DeadlineIn(timeout_ms);
  std::array<std::uint8_t, 4096> chunk;
  while (true) {
    LinkReceived received = FromDecoder();
    if (received.status != LinkReceiveStatus::kTimeout) return received;
    if (closed_) return {LinkReceiveStatus::kClosed, {}, "link closed by the peer", {}};
    const StreamRead got = stream_->ReadSome(chunk, MillisecondsLeft(deadline));
    switch (got.status) {
      case StreamStatus::kData:
        decoder_.Feed(std::span<const std::uint8_t>(chunk.data(), got.bytes));
        continue;
      case StreamStatus::kClosed:
        closed_ = true;
        continue;  // frames already buffered are still delivered first
      case StreamStatus::kTimeout:
        return {};
      case StreamStatus::kError:
        return {LinkReceiveStatus::kSocketError, {}, got.error, {}};
    }
  }
}

LinkListener::LinkListener(std::unique_ptr<Acceptor> acceptor) : acceptor_(std::move(acceptor)) {}
LinkListener::~LinkListener() = default;

rig::Result<std::unique_ptr<LinkListener>> LinkListener::Listen(const std::string& address,
                                                                std::uint16_t port) {
  boost::system::error_code error;
  const asio::ip::address ip = asio::ip::make_address(address, error);
  if (error) return rig::MakeError("link address " + address + ": " + error.message());
  auto acceptor = std::make_unique<Acceptor>();
  const tcp::endpoint local(ip, port);
  const auto fail = [&](const char* what) -> rig::Result<std::unique_ptr<LinkListener>> {
    return rig::MakeError(std::string("link ") + what + " " + address + ":" + std::to_string(port) +
                          ": " + error.message());
  };
  if (acceptor->acceptor.open(local.protocol(), error)) return fail("open");
  acceptor->acceptor.set_option(tcp::acceptor::reuse_address(true), error);
  if (acceptor->acceptor.bind(local, error)) return fail("bind");
  if (acceptor->acceptor.listen(kListenBacklog, error)) return fail("listen on");
  if (acceptor->acceptor.non_blocking(true, error)) return fail("set non-blocking on");
  return std::unique_ptr<LinkListener>(new LinkListener(std::move(acceptor)));
}

std::uint16_t LinkListener::port() const {
  boost::system::error_code error;
  return acceptor_->acceptor.local_endpoint(error).port();
}

rig::Result<std::unique_ptr<LinkConnection>> LinkListener::Accept(int timeout_ms) {
  auto accepted = AcceptStream(timeout_ms);
  if (!accepted) return accepted.error();
  return std::make_unique<LinkConnection>(std::move(accepted.value().stream),
                                          std::move(accepted.value().peer));
}

rig::Result<LinkListener::AcceptedStream> LinkListener::AcceptStream(int timeout_ms) {
  const Deadline deadline = DeadlineIn(timeout_ms);
  const int fd = acceptor_->acceptor.native_handle();
  while (true) {
    auto socket = std::make_shared<TcpSocket>();
    boost::system::error_code error;
    acceptor_->acceptor.accept(socket->socket, error);
    if (!error) {
      socket->socket.non_blocking(true, error);
      socket->socket.set_option(tcp::no_delay(true), error);
      const tcp::endpoint remote = socket->socket.remote_endpoint(error);
      std::string peer = error ? "(disconnected)"
                               : remote.address().to_string() + ":" + std::to_string(remote.port());
      return AcceptedStream{TcpStream(std::move(socket), "link"), std::move(peer)};
    }
    if (error != asio::error::would_block && error != asio::error::try_again &&
        error != asio::error::interrupted) {
      return rig::MakeError("link accept: " + error.message());
    }
    const int ready = WaitFor(fd, POLLIN, deadline);
    if (ready == 0) {
      return rig::MakeError(rig::ErrorCode::kTimeout, "no connection on the link within " +
                                                          std::to_string(timeout_ms) + " ms");
    }
    if (ready < 0) return rig::MakeError(ErrnoText("link accept poll"));
  }
}

}  // namespace hilrig::host
