// A ByteStream over a non-blocking file descriptor (a serial device, a TCP socket): the waiting
// and the named errors the openers in open_byte_stream.h share. The object that owns the
// descriptor (a Boost.Asio serial port or socket) is kept alive type-erased, so that this header
// stays free of Asio.
#pragma once

#include <memory>
#include <string>

#include "host/link/byte_stream.h"

namespace hilrig::host {

class FdByteStream final : public ByteStream {
 public:
  // `fd` must be non-blocking and stay open while `owner` lives. `socket`: write with send(2) and
  // MSG_NOSIGNAL, so a vanished peer is an error value and never SIGPIPE.
  FdByteStream(int fd, bool socket, std::string name, std::shared_ptr<void> owner);

  rig::Result<void> WriteAll(std::span<const std::uint8_t> bytes, int timeout_ms) override;
  StreamRead ReadSome(std::span<std::uint8_t> out, int timeout_ms) override;
  std::string name() const override { return name_; }

 private:
  int fd_;
  bool socket_;
  std::string name_;
  std::shared_ptr<void> owner_;
  bool closed_ = false;
};

}  // namespace hilrig::host
