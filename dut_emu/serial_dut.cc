#include "dut_emu/serial_dut.h"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <span>
#include <string_view>
#include <utility>

#include "dut_emu/dut_emu_server.h"
#include "dut_fw/serial_dut_session.h"
#include "rig/clock.h"
#include "rig/command_args.h"

namespace hilrig::dut_emu {
namespace {

constexpr int kStopCheckMs = 100;  // how often a waiting DUT looks at stop_requested

std::optional<speed_t> TermiosSpeed(std::uint32_t baud) {
  static constexpr std::pair<std::uint32_t, speed_t> kSpeeds[] = {
      {9600, B9600},      {19200, B19200},     {38400, B38400},     {57600, B57600},
      {115200, B115200},  {230400, B230400},   {460800, B460800},   {500000, B500000},
      {921600, B921600},  {1000000, B1000000}, {2000000, B2000000}, {3000000, B3000000},
      {4000000, B4000000}};
  for (const auto& [rate, speed] : kSpeeds) {
    if (rate == baud) return speed;
  }
  return std::nullopt;
}

std::string Errno(const std::string& what, const std::string& path) {
  return what + " " + path + ": " + std::strerror(errno);
}

// A tty opened non-blocking in raw mode (8N1, no echo, no line discipline), closed on exit.
class RawTty {
 public:
  static rig::Result<RawTty> Open(const std::string& path, speed_t speed) {
    const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return rig::MakeError(Errno("cannot open", path));
    RawTty tty(fd);
    termios mode{};
    if (::tcgetattr(fd, &mode) != 0) return rig::MakeError(Errno("not a terminal:", path));
    ::cfmakeraw(&mode);
    mode.c_cflag |= CLOCAL | CREAD;
    if (::cfsetispeed(&mode, speed) != 0 || ::cfsetospeed(&mode, speed) != 0 ||
        ::tcsetattr(fd, TCSANOW, &mode) != 0) {
      return rig::MakeError(Errno("cannot set raw mode on", path));
    }
    return tty;
  }
  RawTty(RawTty&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  RawTty& operator=(RawTty&&) = delete;
  ~RawTty() {
    if (fd_ >= 0) ::close(fd_);
  }
  int fd() const { return fd_; }

 private:
  explicit RawTty(int fd) : fd_(fd) {}
  int fd_;
};

// Writes whole frames, waiting for room when the line is full; a failure is kept for the loop.
class TtySink final : public dut_fw::LineSink {
 public:
  explicit TtySink(int fd) : fd_(fd) {}
  void Write(std::span<const std::uint8_t> bytes) override {
    while (!bytes.empty() && error_ == 0) {
      const ssize_t written = ::write(fd_, bytes.data(), bytes.size());
      if (written > 0) {
        bytes = bytes.subspan(std::size_t(written));
      } else if (written < 0 && (errno == EAGAIN || errno == EINTR)) {
        pollfd out{fd_, POLLOUT, 0};
        ::poll(&out, 1, kStopCheckMs);
      } else {
        error_ = written < 0 ? errno : EIO;
      }
    }
  }
  int error() const { return error_; }

 private:
  int fd_;
  int error_ = 0;
};

// The bridge line's bytes as they are there; without a bridge line, never any.
class TtySource final : public dut_fw::ByteSource {
 public:
  explicit TtySource(int fd) : fd_(fd) {}
  std::optional<std::uint8_t> ReadByte() override {
    if (at_ == size_) {
      if (fd_ < 0) return std::nullopt;
      const ssize_t got = ::read(fd_, buffer_.data(), buffer_.size());
      if (got <= 0) return std::nullopt;
      at_ = 0;
      size_ = std::size_t(got);
    }
    return buffer_[at_++];
  }

 private:
  int fd_;
  std::array<std::uint8_t, 256> buffer_{};
  std::size_t at_ = 0;
  std::size_t size_ = 0;
};

class HostClock final : public dut_fw::MonotonicClock {
 public:
  std::int64_t NowNs() override { return clock_.NowNs(); }

 private:
  rig::SteadyClock clock_;
};

// The host does not measure the step's work: work_cycles reads 0.
class NoCycles final : public dut_fw::CycleCounter {
 public:
  std::uint32_t Cycles() override { return 0; }
};

}  // namespace

const char* const kSerialDutUsage =
    "   or: dut_emu --serial PATH[,baud=N][,bridge=PATH2][,bridge_baud=N]\n"
    "Speaks the serial HIL link on the tty PATH (raw mode, 2000000 baud unless baud=N), reading\n"
    "the sensor nodes' UART bridge from PATH2 (921600 baud unless bridge_baud=N), until a\n"
    "signal stops it or the line closes.\n";

rig::Result<SerialDutOptions> ParseSerialSpec(const std::string& spec) {
  SerialDutOptions options;
  std::size_t start = 0;
  bool first = true;
  while (start <= spec.size()) {
    const std::size_t comma = std::min(spec.find(',', start), spec.size());
    const std::string part = spec.substr(start, comma - start);
    start = comma + 1;
    if (first) {
      if (part.empty()) return rig::MakeError("--serial \"" + spec + "\": expected a tty path");
      options.link_path = part;
      first = false;
    } else if (part.rfind("baud=", 0) == 0 || part.rfind("bridge_baud=", 0) == 0) {
      const std::size_t equals = part.find('=');
      const std::string key = part.substr(0, equals);
      auto baud = rig::ParseNumber<std::uint32_t>(part.substr(equals + 1), "--serial " + key);
      if (!baud) return baud.error();
      if (!TermiosSpeed(baud.value())) {
        return rig::MakeError("--serial " + part + ": not a rate termios has");
      }
      (key == "baud" ? options.baud : options.bridge_baud) = baud.value();
    } else if (part.rfind("bridge=", 0) == 0 && part.size() > 7) {
      options.bridge_path = part.substr(7);
    } else {
      return rig::MakeError("--serial \"" + spec + "\": unknown part \"" + part +
                            "\" (expected baud=N, bridge=PATH or bridge_baud=N)");
    }
  }
  return options;
}

int RunSerialDut(const SerialDutOptions& options, const std::atomic<bool>* stop_requested,
                 std::ostream& log) {
  auto link = RawTty::Open(options.link_path, *TermiosSpeed(options.baud));
  if (!link) {
    log << "dut_emu: " << link.error().message << "\n";
    return kExitFailed;
  }
  std::optional<RawTty> bridge;
  if (options.bridge_path) {
    auto opened = RawTty::Open(*options.bridge_path, *TermiosSpeed(options.bridge_baud));
    if (!opened) {
      log << "dut_emu: " << opened.error().message << "\n";
      return kExitFailed;
    }
    bridge.emplace(std::move(opened).value());
  }
  TtySink sink(link.value().fd());
  TtySource bridge_source(bridge ? bridge->fd() : -1);
  HostClock clock;
  NoCycles cycles;
  const std::string name = "dut_emu " + std::to_string(::getpid());
  const dut_fw::TargetDescription target{name, "host", 0, 0, 0, 0};
  dut_fw::SerialDutSession<float> session(sink, bridge_source, clock, cycles, target);
  std::array<std::uint8_t, 512> received{};
  while (stop_requested == nullptr || !stop_requested->load()) {
    pollfd in{link.value().fd(), POLLIN, 0};
    if (::poll(&in, 1, kStopCheckMs) <= 0) continue;
    const ssize_t got = ::read(link.value().fd(), received.data(), received.size());
    if (got < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (got <= 0) {
      // A pseudo-terminal whose other side closed reads EIO; a tty that went away, 0.
      log << "dut_emu: the line " << options.link_path << " closed\n";
      return session.phase() == dut_fw::SerialDutPhase::kRunning ? kExitFailed : kExitOk;
    }
    for (ssize_t i = 0; i < got; ++i) session.OnLinkByte(received[std::size_t(i)]);
    if (sink.error() != 0) {
      log << "dut_emu: cannot write to " << options.link_path << ": " << std::strerror(sink.error())
          << "\n";
      return kExitFailed;
    }
  }
  return kExitOk;
}

}  // namespace hilrig::dut_emu
