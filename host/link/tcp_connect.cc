#include "host/link/tcp_connect.h"

#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "host/link/poll_wait.h"
#include "rig/stop_request.h"

namespace hilrig::host {

namespace asio = boost::asio;
using asio::ip::tcp;

namespace {

constexpr int kStopCheckMs = 100;  // how often a pending connect looks at the stop request

enum class ConnectWait { kDone, kTimedOut, kStopped };

// Waits for the pending connect on fd to finish (writable, or failed: the caller reads SO_ERROR),
// a slice at a time so that a stop request ends the wait within kStopCheckMs.
ConnectWait WaitConnected(int fd, int timeout_ms, const std::atomic<bool>* stop_requested) {
  const Deadline deadline = DeadlineIn(timeout_ms);
  while (true) {
    if (rig::StopRequested(stop_requested)) return ConnectWait::kStopped;
    const int left_ms = MillisecondsLeft(deadline);
    const int ready = WaitFor(fd, POLLOUT, DeadlineIn(std::min(left_ms, kStopCheckMs)));
    if (ready < 0) return ConnectWait::kTimedOut;  // poll itself failed: as good as no answer
    if (ready > 0) return ConnectWait::kDone;
    if (left_ms <= kStopCheckMs) return ConnectWait::kTimedOut;
  }
}

}  // namespace

rig::Result<void> ConnectWithin(tcp::socket& socket, const std::string& host, std::uint16_t port,
                                int timeout_ms, const std::string& what,
                                const std::atomic<bool>* stop_requested) {
  boost::system::error_code error;
  const asio::ip::address address = asio::ip::make_address(host, error);
  if (error) return rig::MakeError(what + " address " + host + ": " + error.message());
  const tcp::endpoint peer(address, port);
  const std::string where = what + " to " + host + ":" + std::to_string(port);
  if (socket.open(peer.protocol(), error)) return rig::MakeError(where + ": " + error.message());
  socket.non_blocking(true, error);  // the link's reads and writes poll, and never block
  if (error) return rig::MakeError(where + ": " + error.message());
  const int fd = socket.native_handle();
  // connect(2) on the descriptor itself: Asio's synchronous connect waits for the handshake
  // with no timeout whatever the socket's mode, so a peer that drops the SYN held it for the
  // kernel's two minutes of retries.
  const bool pending = ::connect(fd, peer.data(), static_cast<socklen_t>(peer.size())) != 0;
  if (pending && errno != EINPROGRESS) return rig::MakeError(where + ": " + std::strerror(errno));
  if (pending) {
    const ConnectWait waited = WaitConnected(fd, timeout_ms, stop_requested);
    if (waited == ConnectWait::kStopped) {
      return rig::MakeError(rig::ErrorCode::kInterrupted, where + " stopped");
    }
    if (waited == ConnectWait::kTimedOut) {
      return rig::MakeError(rig::ErrorCode::kTimeout, where + " timed out");
    }
    int status = 0;
    socklen_t length = sizeof(status);
    ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &status, &length);
    if (status != 0) return rig::MakeError(where + ": " + std::strerror(status));
  }
  socket.set_option(tcp::no_delay(true), error);
  return {};
}

}  // namespace hilrig::host
