// The UDP socket of a link whose peer announces itself: no peer to send to until one speaks, then
// datagrams both ways, whole. The peer here is a plain socket of the test's own.
#include "host/link/udp_socket.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <vector>

namespace hilrig::host {
namespace {

struct Peer {
  Peer() {
    fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&local), sizeof local);
  }
  ~Peer() { ::close(fd); }
  void SendTo(std::uint16_t port, const std::vector<std::uint8_t>& bytes) const {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    to.sin_port = htons(port);
    ::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
  }
  std::vector<std::uint8_t> Receive() const {
    std::array<std::uint8_t, 64> buffer{};
    const ssize_t got = ::recv(fd, buffer.data(), buffer.size(), 0);
    return {buffer.begin(), buffer.begin() + std::max<ssize_t>(got, 0)};
  }
  int fd = -1;
};

TEST(UdpSocketTest, LearnsItsPeerFromTheFirstDatagramAndAnswersIt) {
  auto socket = UdpSocket::Bind("127.0.0.1", 0);
  ASSERT_TRUE(socket) << socket.error().message;
  UdpSocket& rig = *socket.value();
  EXPECT_NE(rig.port(), 0);
  EXPECT_FALSE(rig.has_peer());
  EXPECT_FALSE(rig.Send(std::vector<std::uint8_t>{1}));  // nobody to send to yet
  std::array<std::uint8_t, 8> buffer{};
  auto nothing = rig.Receive(buffer, 0);
  ASSERT_TRUE(nothing);
  EXPECT_FALSE(nothing.value());

  const Peer peer;
  peer.SendTo(rig.port(), {1, 2, 3});
  auto received = rig.Receive(buffer, 1000);
  ASSERT_TRUE(received);
  ASSERT_TRUE(received.value());
  EXPECT_EQ(*received.value(), 3u);
  EXPECT_EQ(buffer[2], 3);
  EXPECT_TRUE(rig.has_peer());
  EXPECT_EQ(rig.peer().rfind("127.0.0.1:", 0), 0u);

  ASSERT_TRUE(rig.Send(std::vector<std::uint8_t>{9, 8}));
  EXPECT_EQ(peer.Receive(), (std::vector<std::uint8_t>{9, 8}));
}

TEST(UdpSocketTest, RefusesAnAddressThatIsNotIpv4) {
  auto socket = UdpSocket::Bind("localhost", 0);
  ASSERT_FALSE(socket);
  EXPECT_NE(socket.error().message.find("not an IPv4 address"), std::string::npos);
}

}  // namespace
}  // namespace hilrig::host
