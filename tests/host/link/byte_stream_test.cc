// The byte streams a serial link runs on: a serial device in raw mode (on a pseudo-terminal pair,
// the kernel's own tty layer) and a TCP connection on loopback. Nothing waits on wall time: every
// read is of bytes already written, or of a closed peer.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <pty.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <string>
#include <vector>

#include "host/link/open_byte_stream.h"

namespace hilrig::host {
namespace {

// Reads from `stream` until `count` bytes arrived (they were written before) or it stops giving.
std::vector<std::uint8_t> ReadCount(ByteStream& stream, std::size_t count) {
  std::vector<std::uint8_t> got;
  std::array<std::uint8_t, 64> chunk;
  while (got.size() < count) {
    const StreamRead read = stream.ReadSome(chunk, 5000);
    if (read.status != StreamStatus::kData) break;
    got.insert(got.end(), chunk.begin(), chunk.begin() + read.bytes);
  }
  return got;
}

// Bytes a cooked terminal would change or eat: CR (mapped to LF), ^C (a signal), XON/XOFF (flow
// control), a zero, LF, and a byte with the top bit set.
const std::vector<std::uint8_t> kTerminalSensitive = {'\r', 0x03, 0x11, 0x13,
                                                      0x00, '\n', 0xFF, 0x7F};

struct Pty {
  int master = -1;
  std::string slave_path;
  Pty() {
    int slave = -1;
    std::array<char, 128> name{};
    if (::openpty(&master, &slave, name.data(), nullptr, nullptr) == 0) {
      slave_path = name.data();
      ::close(slave);  // the stream opens the device by its name
    }
  }
  ~Pty() {
    if (master >= 0) ::close(master);
  }
};

TEST(SerialPortStreamTest, CarriesEveryByteUnchangedBothWays) {
  Pty pty;
  ASSERT_GE(pty.master, 0);
  auto stream = OpenSerialPort(pty.slave_path, 2'000'000);  // the link's default rate
  ASSERT_TRUE(stream) << stream.error().message;
  EXPECT_NE(stream.value()->name().find("2000000 baud"), std::string::npos);

  ASSERT_EQ(::write(pty.master, kTerminalSensitive.data(), kTerminalSensitive.size()),
            ssize_t(kTerminalSensitive.size()));
  EXPECT_EQ(ReadCount(*stream.value(), kTerminalSensitive.size()), kTerminalSensitive);

  ASSERT_TRUE(stream.value()->WriteAll(kTerminalSensitive, 1000));
  std::vector<std::uint8_t> back(kTerminalSensitive.size());
  std::size_t got = 0;
  while (got < back.size()) {
    const ssize_t n = ::read(pty.master, back.data() + got, back.size() - got);
    ASSERT_GT(n, 0);
    got += std::size_t(n);
  }
  EXPECT_EQ(back, kTerminalSensitive);  // no LF -> CRLF on output either
}

TEST(SerialPortStreamTest, ReportsNothingWaitingAndThenTheHangUp) {
  Pty pty;
  ASSERT_GE(pty.master, 0);
  auto stream = OpenSerialPort(pty.slave_path, 115200);
  ASSERT_TRUE(stream) << stream.error().message;
  std::array<std::uint8_t, 8> chunk;
  EXPECT_EQ(stream.value()->ReadSome(chunk, 0).status, StreamStatus::kTimeout);
  ::close(pty.master);
  pty.master = -1;
  const StreamRead read = stream.value()->ReadSome(chunk, 5000);
  EXPECT_EQ(read.status, StreamStatus::kClosed);
  EXPECT_NE(read.error.find(pty.slave_path), std::string::npos) << read.error;
}

TEST(SerialPortStreamTest, NamesAMissingDeviceAndTheCause) {
  auto stream = OpenSerialPort("/dev/hilrig-no-such-tty", 115200);
  ASSERT_FALSE(stream);
  EXPECT_NE(stream.error().message.find("/dev/hilrig-no-such-tty"), std::string::npos);
  EXPECT_NE(stream.error().message.find("No such file"), std::string::npos)
      << stream.error().message;
}

struct Listener {
  int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  std::uint16_t port = 0;
  Listener() {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof(address);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&address), length) == 0 && ::listen(fd, 4) == 0 &&
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
      port = ntohs(address.sin_port);
    }
  }
  ~Listener() { ::close(fd); }
};

TEST(SerialPortStreamTest, ParsesADeviceAndItsBaudAsACommandLineNamesThem) {
  auto plain = ParseSerialDevice("/dev/ttyACM0", 921600);
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  EXPECT_EQ(plain.value().device, "/dev/ttyACM0");
  EXPECT_EQ(plain.value().baud, 921600u);
  auto fast = ParseSerialDevice("/dev/ttyUSB1,baud=2000000", 921600);
  ASSERT_TRUE(fast.ok()) << fast.error().message;
  EXPECT_EQ(fast.value().baud, 2000000u);
  EXPECT_EQ(ParseSerialDevice(",baud=9600", 1).error().message, "no device");
  EXPECT_EQ(ParseSerialDevice("/dev/x,speed=1", 1).error().message,
            "unknown option \"speed=1\" (expected baud=N)");
  for (const char* bad : {"/dev/x,baud=0", "/dev/x,baud=12000001", "/dev/x,baud=9k"}) {
    EXPECT_FALSE(ParseSerialDevice(bad, 1).ok()) << bad;
  }
}

TEST(TcpByteStreamTest, CarriesBytesBothWaysAndSeesTheClose) {
  Listener listener;
  ASSERT_NE(listener.port, 0);
  auto stream = ConnectTcpStream("127.0.0.1", listener.port, 5000);
  ASSERT_TRUE(stream) << stream.error().message;
  const int peer = ::accept(listener.fd, nullptr, nullptr);
  ASSERT_GE(peer, 0);

  ASSERT_EQ(::write(peer, kTerminalSensitive.data(), kTerminalSensitive.size()),
            ssize_t(kTerminalSensitive.size()));
  EXPECT_EQ(ReadCount(*stream.value(), kTerminalSensitive.size()), kTerminalSensitive);
  ASSERT_TRUE(stream.value()->WriteAll(kTerminalSensitive, 1000));
  std::vector<std::uint8_t> back(kTerminalSensitive.size());
  ASSERT_EQ(::recv(peer, back.data(), back.size(), MSG_WAITALL), ssize_t(back.size()));
  EXPECT_EQ(back, kTerminalSensitive);

  std::array<std::uint8_t, 8> chunk;
  EXPECT_EQ(stream.value()->ReadSome(chunk, 0).status, StreamStatus::kTimeout);
  ::close(peer);
  EXPECT_EQ(stream.value()->ReadSome(chunk, 5000).status, StreamStatus::kClosed);
  // A write to the closed peer is an error value, not SIGPIPE.
  rig::Result<void> written = stream.value()->WriteAll(kTerminalSensitive, 1000);
  for (int attempt = 0; attempt < 3 && written; ++attempt) {
    written = stream.value()->WriteAll(kTerminalSensitive, 1000);
  }
  EXPECT_FALSE(written);
}

TEST(TcpByteStreamTest, NamesARefusedConnection) {
  std::uint16_t port = 0;
  {
    Listener closed_soon;
    port = closed_soon.port;
  }
  auto stream = ConnectTcpStream("127.0.0.1", port, 5000);
  ASSERT_FALSE(stream);
  EXPECT_NE(stream.error().message.find("127.0.0.1:" + std::to_string(port)), std::string::npos);
  EXPECT_NE(stream.error().message.find("refused"), std::string::npos) << stream.error().message;
}

TEST(TcpByteStreamTest, FindsAFreeLoopbackPort) {
  auto port = FreeLoopbackPort();
  ASSERT_TRUE(port) << port.error().message;
  EXPECT_NE(port.value(), 0);
}

}  // namespace
}  // namespace hilrig::host
