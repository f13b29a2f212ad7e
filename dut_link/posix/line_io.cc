#include "dut_link/posix/line_io.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <utility>

namespace hilrig::dut_link {
namespace {

constexpr int kStopCheckMs = 100;  // how often a waiting DUT looks at `stop`

std::atomic<bool> g_stop_requested{false};  // set from the signal handler; lock-free
static_assert(std::atomic<bool>::is_always_lock_free);

void RequestStop(int /*signal*/) { g_stop_requested.store(true); }

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

std::string Errno(const std::string& what) { return what + ": " + std::strerror(errno); }

// Waits for a non-blocking connect to finish; 0 or the errno it failed with.
int FinishConnect(int fd, int timeout_ms) {
  pollfd out{fd, POLLOUT, 0};
  const int ready = ::poll(&out, 1, timeout_ms);
  if (ready == 0) return ETIMEDOUT;
  if (ready < 0) return errno;
  int error = 0;
  socklen_t size = sizeof error;
  if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &size) != 0) return errno;
  return error;
}

}  // namespace

OwnedLine OwnedLine::Failed(std::string error) {
  OwnedLine line;
  line.error_ = std::move(error);
  return line;
}

OwnedLine::OwnedLine(OwnedLine&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), error_(std::move(other.error_)) {}

OwnedLine& OwnedLine::operator=(OwnedLine&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    error_ = std::move(other.error_);
  }
  return *this;
}

OwnedLine::~OwnedLine() {
  if (fd_ >= 0) ::close(fd_);
}

bool IsTermiosRate(std::uint32_t baud) { return TermiosSpeed(baud).has_value(); }

OwnedLine OpenRawTty(const std::string& path, std::uint32_t baud) {
  const std::optional<speed_t> speed = TermiosSpeed(baud);
  if (!speed) return OwnedLine::Failed(std::to_string(baud) + " baud: not a rate termios has");
  OwnedLine tty(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC));
  if (!tty.ok()) return OwnedLine::Failed(Errno("cannot open " + path));
  termios mode{};
  if (::tcgetattr(tty.fd(), &mode) != 0) return OwnedLine::Failed(Errno("not a terminal: " + path));
  ::cfmakeraw(&mode);
  mode.c_cflag |= CLOCAL | CREAD;
  if (::cfsetispeed(&mode, *speed) != 0 || ::cfsetospeed(&mode, *speed) != 0 ||
      ::tcsetattr(tty.fd(), TCSANOW, &mode) != 0) {
    return OwnedLine::Failed(Errno("cannot set raw mode on " + path));
  }
  return tty;
}

OwnedLine ConnectTcpLine(const std::string& host, std::uint16_t port, int timeout_ms) {
  const std::string where = host + ":" + std::to_string(port);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (const int status = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found);
      status != 0) {
    return OwnedLine::Failed("cannot resolve " + where + ": " + ::gai_strerror(status));
  }
  std::string last_error = "no address";
  for (const addrinfo* address = found; address != nullptr; address = address->ai_next) {
    OwnedLine socket(
        ::socket(address->ai_family, address->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!socket.ok()) {
      last_error = std::strerror(errno);
      continue;
    }
    int error = ::connect(socket.fd(), address->ai_addr, address->ai_addrlen) == 0 ? 0 : errno;
    if (error == EINPROGRESS) error = FinishConnect(socket.fd(), timeout_ms);
    if (error == 0) {
      const int on = 1;  // a step's answer is one small frame: send it now
      ::setsockopt(socket.fd(), IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
      ::freeaddrinfo(found);
      return socket;
    }
    last_error = std::strerror(error);
  }
  ::freeaddrinfo(found);
  return OwnedLine::Failed("cannot connect to " + where + ": " + last_error);
}

FdLineSink::FdLineSink(int fd) : fd_(fd) {
  struct stat status {};
  socket_ = ::fstat(fd, &status) == 0 && S_ISSOCK(status.st_mode);
}

void FdLineSink::Write(std::span<const std::uint8_t> bytes) {
  while (!bytes.empty() && error_ == 0) {
    const ssize_t result = socket_ ? ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL)
                                   : ::write(fd_, bytes.data(), bytes.size());
    if (result > 0) {
      bytes = bytes.subspan(std::size_t(result));
    } else if (result < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd out{fd_, POLLOUT, 0};
      ::poll(&out, 1, kStopCheckMs);
    } else {
      error_ = result < 0 ? errno : EIO;
    }
  }
}

std::optional<std::uint8_t> FdByteSource::ReadByte() {
  if (at_ == size_) {
    if (fd_ < 0) return std::nullopt;
    const ssize_t got = ::read(fd_, buffer_.data(), buffer_.size());
    if (got <= 0) return std::nullopt;
    at_ = 0;
    size_ = std::size_t(got);
  }
  return buffer_[at_++];
}

std::int64_t SteadyMonotonicClock::NowNs() {
  timespec now{};
  ::clock_gettime(CLOCK_MONOTONIC, &now);
  return std::int64_t(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

std::optional<std::array<std::uint8_t, 16>> LoadLinkToken(const std::string& token_file,
                                                          std::string& error) {
  std::string text;
  const std::string source = token_file.empty() ? "HILRIG_LINK_TOKEN" : token_file;
  if (token_file.empty()) {
    const char* value = std::getenv("HILRIG_LINK_TOKEN");
    if (value == nullptr) {
      error = "no link token: pass --token-file PATH or set HILRIG_LINK_TOKEN";
      return std::nullopt;
    }
    text = value;
  } else {
    std::ifstream file(token_file);
    if (!file || !std::getline(file, text)) {
      error = "cannot read the link token from " + token_file;
      return std::nullopt;
    }
  }
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  std::array<std::uint8_t, 16> token{};
  const auto nibble = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  bool ok = text.size() == 2 * token.size();
  for (std::size_t i = 0; ok && i < token.size(); ++i) {
    const int high = nibble(text[2 * i]);
    const int low = nibble(text[2 * i + 1]);
    ok = high >= 0 && low >= 0;
    token[i] = std::uint8_t(16 * high + low);
  }
  if (!ok) {
    error = source + ": a link token is 32 hex digits";
    return std::nullopt;
  }
  return token;
}

const std::atomic<bool>* StopOnSignals() {
  struct sigaction action {};
  action.sa_handler = RequestStop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
  signal(SIGPIPE, SIG_IGN);
  return &g_stop_requested;
}

LineEnd ServeLine(SerialDutSession& session, int link_fd, const FdLineSink& sink,
                  const std::atomic<bool>* stop) {
  std::array<std::uint8_t, 512> received{};
  while (stop == nullptr || !stop->load()) {
    pollfd in{link_fd, POLLIN, 0};
    if (::poll(&in, 1, kStopCheckMs) <= 0) continue;
    const ssize_t got = ::read(link_fd, received.data(), received.size());
    if (got < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    // A pseudo-terminal whose other side closed reads EIO, a tty that went away or a closed
    // socket 0: both are the line closing.
    if (got == 0 || (got < 0 && errno == EIO)) {
      return session.phase() == SerialDutPhase::kRunning ? LineEnd::kClosedMidRun
                                                         : LineEnd::kClosedIdle;
    }
    if (got < 0) return LineEnd::kReadFailed;
    for (ssize_t i = 0; i < got; ++i) session.OnLinkByte(received[std::size_t(i)]);
    if (sink.error() != 0) return LineEnd::kWriteFailed;
  }
  return LineEnd::kStopped;
}

}  // namespace hilrig::dut_link
