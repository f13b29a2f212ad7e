// A loopback port whose connects stay pending, like those to a peer that drops the SYN: a listening
// socket with a backlog of 0 whose one queue place is taken, so the kernel drops every further
// SYN. For tests of connect timeouts and stop requests; closed when it goes out of scope.
#pragma once

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <memory>

#include "host/link/hil_link_socket.h"

namespace hilrig::host {

class FullListener {
 public:
  FullListener() {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof(address);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&address), length) != 0 || ::listen(fd_, 0) != 0 ||
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
      ADD_FAILURE() << "cannot listen on loopback";
    }
    port_ = ntohs(address.sin_port);
    auto filler = LinkConnection::Connect("127.0.0.1", port_, 2000);
    if (!filler) ADD_FAILURE() << "the first connect was not answered: " << filler.error().message;
    if (filler) filler_ = std::move(filler).value();
  }
  ~FullListener() { ::close(fd_); }
  FullListener(const FullListener&) = delete;
  FullListener& operator=(const FullListener&) = delete;

  std::uint16_t port() const { return port_; }

 private:
  int fd_ = -1;
  std::uint16_t port_ = 0;
  std::unique_ptr<LinkConnection> filler_;  // the connection in the queue's one place
};

}  // namespace hilrig::host
