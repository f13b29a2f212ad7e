// A UDP socket for a message link whose peer announces itself (MAVLink's offboard API port, which
// a flight stack sends its heartbeat to): bound to one address, it learns its peer from the first
// datagram that arrives and sends to it from then on. Datagrams are kept whole; a send never
// waits. Closed by destruction.
//
// Threading: one socket is used from one thread at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "rig/result.h"

namespace hilrig::host {

class UdpSocket {
 public:
  // Binds an IPv4 address and port (0: a free one, see port()). Fails with the address and the
  // system's reason.
  static rig::Result<std::unique_ptr<UdpSocket>> Bind(const std::string& address,
                                                      std::uint16_t port);
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  std::uint16_t port() const { return port_; }
  // Whether a datagram has arrived yet, and from where ("127.0.0.1:14580").
  bool has_peer() const { return has_peer_; }
  std::string peer() const;

  // One datagram into `out`, waiting at most timeout_ms (0: not at all): its size, or nullopt when
  // none came. A datagram longer than `out` is cut to it. Fails only when the socket does.
  // Does not allocate.
  rig::Result<std::optional<std::size_t>> Receive(std::span<std::uint8_t> out, int timeout_ms);
  // Sends one datagram to the peer without waiting. Fails without a peer, or when the system
  // refuses it (a full buffer included). Does not allocate.
  rig::Result<void> Send(std::span<const std::uint8_t> datagram);

 private:
  UdpSocket(int fd, std::uint16_t port) : fd_(fd), port_(port) {}

  int fd_;
  std::uint16_t port_;
  bool has_peer_ = false;
  std::uint32_t peer_address_ = 0;  // network byte order
  std::uint16_t peer_port_ = 0;     // network byte order
};

}  // namespace hilrig::host
