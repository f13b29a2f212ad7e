#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include "host/link/fd_byte_stream.h"
#include "host/link/open_byte_stream.h"
#include "host/link/tcp_connect.h"

namespace hilrig::host {
namespace {

namespace asio = boost::asio;
using asio::ip::tcp;

struct TcpSocket {
  asio::io_context io;
  tcp::socket socket{io};
};

}  // namespace

rig::Result<std::unique_ptr<ByteStream>> ConnectTcpStream(const std::string& host,
                                                          std::uint16_t port, int timeout_ms) {
  auto tcp_socket = std::make_shared<TcpSocket>();
  if (auto connected = ConnectWithin(tcp_socket->socket, host, port, timeout_ms, "tcp connect");
      !connected) {
    return connected.error();
  }
  const int fd = tcp_socket->socket.native_handle();
  return std::unique_ptr<ByteStream>(std::make_unique<FdByteStream>(
      fd, /*socket=*/true, "tcp " + host + ":" + std::to_string(port), std::move(tcp_socket)));
}

rig::Result<std::uint16_t> FreeLoopbackPort() {
  asio::io_context io;
  tcp::acceptor acceptor(io);
  boost::system::error_code error;
  const tcp::endpoint local(asio::ip::make_address("127.0.0.1"), 0);
  if (!acceptor.open(local.protocol(), error)) acceptor.bind(local, error);
  if (error) return rig::MakeError(rig::ErrorCode::kIo, "a free loopback port: " + error.message());
  return acceptor.local_endpoint().port();
}

}  // namespace hilrig::host
