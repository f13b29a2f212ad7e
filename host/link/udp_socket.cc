#include "host/link/udp_socket.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "host/link/poll_wait.h"

namespace hilrig::host {
namespace {

rig::Error SystemError(const std::string& what) {
  return rig::MakeError(rig::ErrorCode::kIo, what + ": " + std::strerror(errno));
}

}  // namespace

rig::Result<std::unique_ptr<UdpSocket>> UdpSocket::Bind(const std::string& address,
                                                        std::uint16_t port) {
  const std::string where = "udp " + address + ":" + std::to_string(port);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  local.sin_port = htons(port);
  if (::inet_pton(AF_INET, address.c_str(), &local.sin_addr) != 1) {
    return rig::MakeError(where + ": not an IPv4 address");
  }
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return SystemError(where + ": socket");
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
    const rig::Error error = SystemError(where + ": bind");
    ::close(fd);
    return error;
  }
  socklen_t length = sizeof local;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &length);
  return std::unique_ptr<UdpSocket>(new UdpSocket(fd, ntohs(local.sin_port)));
}

UdpSocket::~UdpSocket() { ::close(fd_); }

std::string UdpSocket::peer() const {
  if (!has_peer_) return "none";
  char text[INET_ADDRSTRLEN] = {};
  in_addr address{peer_address_};
  ::inet_ntop(AF_INET, &address, text, sizeof text);
  return std::string(text) + ":" + std::to_string(ntohs(peer_port_));
}

rig::Result<std::optional<std::size_t>> UdpSocket::Receive(std::span<std::uint8_t> out,
                                                           int timeout_ms) {
  if (timeout_ms > 0 && WaitFor(fd_, POLLIN, DeadlineIn(timeout_ms)) <= 0) {
    return std::optional<std::size_t>();
  }
  sockaddr_in from{};
  socklen_t length = sizeof from;
  const ssize_t got = ::recvfrom(fd_, out.data(), out.size(), MSG_TRUNC,
                                 reinterpret_cast<sockaddr*>(&from), &length);
  if (got < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
      return std::optional<std::size_t>();
    }
    return SystemError("udp port " + std::to_string(port_) + ": receive");
  }
  has_peer_ = true;
  peer_address_ = from.sin_addr.s_addr;
  peer_port_ = from.sin_port;
  return std::optional<std::size_t>(std::min(static_cast<std::size_t>(got), out.size()));
}

rig::Result<void> UdpSocket::Send(std::span<const std::uint8_t> datagram) {
  if (!has_peer_) {
    return rig::MakeError("udp port " + std::to_string(port_) + ": no peer has spoken yet");
  }
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = peer_address_;
  to.sin_port = peer_port_;
  if (::sendto(fd_, datagram.data(), datagram.size(), MSG_NOSIGNAL,
               reinterpret_cast<const sockaddr*>(&to), sizeof to) < 0) {
    return SystemError("udp to " + peer());
  }
  return {};
}

}  // namespace hilrig::host
