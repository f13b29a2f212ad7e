// The runner's end of a serial HIL link for tests that drive a DUT over a real file descriptor (a
// pseudo-terminal to dut_emu --serial, or QEMU's pty for the STM32 image): LinkMessages framed as
// dut_link/line_framing.h frames them, and every wait a poll with a deadline that returns as soon
// as the bytes are there.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dut_link/line_framing.h"
#include "proto/hil_link.pb.h"
#include "tests/support/serial_dut_fakes.h"

namespace hilrig::dut_fw {

// A file descriptor closed with its owner.
class OwnedFd {
 public:
  explicit OwnedFd(int fd = -1) : fd_(fd) {}
  OwnedFd(OwnedFd&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  OwnedFd& operator=(OwnedFd&& other) noexcept {
    std::swap(fd_, other.fd_);
    return *this;
  }
  ~OwnedFd() { Close(); }
  void Close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

// Raw mode (no echo, no line editing, 8-bit clean) on a terminal.
inline void MakeRaw(int fd) {
  termios mode{};
  ASSERT_EQ(::tcgetattr(fd, &mode), 0);
  ::cfmakeraw(&mode);
  ASSERT_EQ(::tcsetattr(fd, TCSANOW, &mode), 0);
}

// A pseudo-terminal pair: the test keeps the master; the DUT opens `slave_path`. The test also
// holds the slave open, in raw mode unless told otherwise, so no byte is cooked before the DUT
// sets its own mode.
struct Pty {
  OwnedFd master;
  OwnedFd slave;
  std::string slave_path;
};

inline Pty OpenPty(bool raw = true) {
  Pty pty;
  pty.master = OwnedFd(::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC));
  EXPECT_GE(pty.master.get(), 0);
  EXPECT_EQ(::grantpt(pty.master.get()), 0);
  EXPECT_EQ(::unlockpt(pty.master.get()), 0);
  pty.slave_path = ::ptsname(pty.master.get());
  pty.slave = OwnedFd(::open(pty.slave_path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC));
  EXPECT_GE(pty.slave.get(), 0);
  if (raw) MakeRaw(pty.slave.get());  // the pair's one line discipline, the master's too
  return pty;
}

inline void WriteAll(int fd, const std::vector<std::uint8_t>& bytes) {
  std::size_t at = 0;
  while (at < bytes.size()) {
    const ssize_t written = ::write(fd, bytes.data() + at, bytes.size() - at);
    if (written > 0) {
      at += std::size_t(written);
    } else {
      pollfd out{fd, POLLOUT, 0};
      ASSERT_GE(::poll(&out, 1, 1000), 0);
    }
  }
}

class SerialLinePeer {
 public:
  explicit SerialLinePeer(int fd) : fd_(fd) {}

  void Send(const proto::LinkMessage& message) { WriteAll(fd_, LineFrame(message)); }

  // The next message the DUT sends; nullopt when none is complete within `timeout_ms`.
  std::optional<proto::LinkMessage> Receive(int timeout_ms) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (true) {
      while (at_ < size_) {
        if (const auto payload = decoder_.Feed(buffer_[at_++])) {
          proto::LinkMessage message;
          if (message.ParseFromArray(payload->data(), int(payload->size()))) return message;
        }
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      pollfd in{fd_, POLLIN, 0};
      if (::poll(&in, 1, int(left.count())) <= 0) continue;
      const ssize_t got = ::read(fd_, buffer_.data(), buffer_.size());
      if (got <= 0) return std::nullopt;
      at_ = 0;
      size_ = std::size_t(got);
    }
  }

 private:
  int fd_;
  dut_link::FrameDecoder<dut_link::kMaxLineMessageBytes> decoder_;
  std::array<std::uint8_t, 4096> buffer_{};
  std::size_t at_ = 0;
  std::size_t size_ = 0;
};

}  // namespace hilrig::dut_fw
