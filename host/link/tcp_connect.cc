#include "host/link/tcp_connect.h"

#include <poll.h>
#include <sys/socket.h>

#include <cstring>

#include "host/link/poll_wait.h"

namespace hilrig::host {

namespace asio = boost::asio;
using asio::ip::tcp;

rig::Result<void> ConnectWithin(tcp::socket& socket, const std::string& host, std::uint16_t port,
                                int timeout_ms, const std::string& what) {
  boost::system::error_code error;
  const asio::ip::address address = asio::ip::make_address(host, error);
  if (error) return rig::MakeError(what + " address " + host + ": " + error.message());
  const tcp::endpoint peer(address, port);
  const std::string where = what + " to " + host + ":" + std::to_string(port);
  if (socket.open(peer.protocol(), error)) return rig::MakeError(where + ": " + error.message());
  socket.non_blocking(true, error);
  const int fd = socket.native_handle();
  socket.connect(peer, error);
  if (error == asio::error::in_progress || error == asio::error::would_block) {
    if (WaitFor(fd, POLLOUT, DeadlineIn(timeout_ms)) <= 0) {
      return rig::MakeError(rig::ErrorCode::kTimeout, where + " timed out");
    }
    int status = 0;
    socklen_t length = sizeof(status);
    ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &status, &length);
    if (status != 0) return rig::MakeError(where + ": " + std::strerror(status));
  } else if (error) {
    return rig::MakeError(where + ": " + error.message());
  }
  socket.set_option(tcp::no_delay(true), error);
  return {};
}

}  // namespace hilrig::host
