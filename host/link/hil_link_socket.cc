#include "host/link/hil_link_socket.h"

#include <poll.h>
#include <sys/socket.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>

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

}  // namespace

struct LinkConnection::Socket {
  asio::io_context io;
  tcp::socket socket{io};
};

struct LinkListener::Acceptor {
  asio::io_context io;
  tcp::acceptor acceptor{io};
};

LinkConnection::LinkConnection(std::unique_ptr<Socket> socket) : socket_(std::move(socket)) {}
LinkConnection::~LinkConnection() = default;

rig::Result<std::unique_ptr<LinkConnection>> LinkConnection::Connect(const std::string& host,
                                                                     std::uint16_t port,
                                                                     int timeout_ms) {
  auto socket = std::make_unique<Socket>();
  if (auto connected = ConnectWithin(socket->socket, host, port, timeout_ms, "link connect");
      !connected) {
    return connected.error();
  }
  return std::unique_ptr<LinkConnection>(new LinkConnection(std::move(socket)));
}

std::string LinkConnection::peer() const {
  boost::system::error_code error;
  const tcp::endpoint remote = socket_->socket.remote_endpoint(error);
  if (error) return "(disconnected)";
  return remote.address().to_string() + ":" + std::to_string(remote.port());
}

rig::Result<void> LinkConnection::Send(const proto::LinkMessage& message, int timeout_ms) {
  auto frame = EncodeLinkFrame(message);
  if (!frame) return frame.error();
  auto sent = SendBytes(frame.value(), timeout_ms);
  if (sent) ++frames_sent_;
  return sent;
}

rig::Result<void> LinkConnection::SendBytes(const std::string& bytes, int timeout_ms) {
  if (closed_) return rig::MakeError(rig::ErrorCode::kLinkClosed, "link closed by the peer");
  const int fd = socket_->socket.native_handle();
  const Deadline deadline = DeadlineIn(timeout_ms);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t wrote =
        ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (wrote > 0) {
      done += static_cast<std::size_t>(wrote);
      continue;
    }
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (WaitFor(fd, POLLOUT, deadline) <= 0) {
        return rig::MakeError(rig::ErrorCode::kTimeout, "link send timed out after " +
                                                            std::to_string(timeout_ms) +
                                                            " ms (the peer does not read)");
      }
      continue;
    }
    if (errno == EPIPE || errno == ECONNRESET) closed_ = true;
    return rig::MakeError(closed_ ? rig::ErrorCode::kLinkClosed : rig::ErrorCode::kIo,
                          ErrnoText("link send"));
  }
  return {};
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
  const int fd = socket_->socket.native_handle();
  std::array<std::uint8_t, 4096> chunk;
  while (true) {
    LinkReceived received = FromDecoder();
    if (received.status != LinkReceiveStatus::kTimeout) return received;
    if (closed_) return {LinkReceiveStatus::kClosed, {}, "link closed by the peer", {}};
    const ssize_t got = ::recv(fd, chunk.data(), chunk.size(), MSG_DONTWAIT);
    if (got > 0) {
      decoder_.Feed(std::span<const std::uint8_t>(chunk.data(), static_cast<std::size_t>(got)));
      continue;
    }
    if (got == 0 || (got < 0 && errno == ECONNRESET)) {
      closed_ = true;
      continue;  // frames already buffered are still delivered first
    }
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      return {LinkReceiveStatus::kSocketError, {}, ErrnoText("link receive"), {}};
    }
    const int ready = WaitFor(fd, POLLIN, deadline);
    if (ready == 0) return {};
    if (ready < 0) return {LinkReceiveStatus::kSocketError, {}, ErrnoText("link poll"), {}};
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
  const Deadline deadline = DeadlineIn(timeout_ms);
  const int fd = acceptor_->acceptor.native_handle();
  while (true) {
    auto socket = std::make_unique<LinkConnection::Socket>();
    boost::system::error_code error;
    acceptor_->acceptor.accept(socket->socket, error);
    if (!error) {
      socket->socket.non_blocking(true, error);
      socket->socket.set_option(tcp::no_delay(true), error);
      return std::unique_ptr<LinkConnection>(new LinkConnection(std::move(socket)));
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
