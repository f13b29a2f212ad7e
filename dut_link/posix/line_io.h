// The DUT side of the HIL link on a POSIX host: what a DUT process (dut_emu --serial, a team's own
// program such as examples/hover_dut) plugs into dut_link/serial_session.h. A line is a file
// descriptor: a tty in raw mode (a serial adapter, a pseudo-terminal) or a TCP connection to the
// rig's `--dut listen:` or `exec:` with `--dut-link line`. The session's platform interfaces over
// descriptors, the steady clock, and the loop that feeds the link line's bytes to the session.
// Errors are values (an empty descriptor and a message naming the path or address and the cause).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "dut_link/serial_session.h"

namespace hilrig::dut_link {

// A descriptor this object closes; `error` says why there is none.
class OwnedLine {
 public:
  OwnedLine() = default;
  static OwnedLine Failed(std::string error);
  explicit OwnedLine(int fd) : fd_(fd) {}
  OwnedLine(OwnedLine&& other) noexcept;
  OwnedLine& operator=(OwnedLine&& other) noexcept;
  ~OwnedLine();

  bool ok() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  const std::string& error() const { return error_; }

 private:
  int fd_ = -1;
  std::string error_;
};

// Whether termios has a constant for `baud`.
bool IsTermiosRate(std::uint32_t baud);
// Opens the tty at `path` non-blocking in raw mode (8N1, no echo, no line discipline) at `baud`.
OwnedLine OpenRawTty(const std::string& path, std::uint32_t baud);
// Connects to host:port (a name or an address), waiting at most timeout_ms; non-blocking after.
OwnedLine ConnectTcpLine(const std::string& host, std::uint16_t port, int timeout_ms);

// Writes whole frames, waiting for room when the line is full; a failure is kept for the loop.
class FdLineSink final : public LineSink {
 public:
  // Looks once whether `fd` is a socket (written with MSG_NOSIGNAL) or a tty.
  explicit FdLineSink(int fd);
  void Write(std::span<const std::uint8_t> bytes) override;
  int error() const { return error_; }  // errno of the first failed write; 0: none

 private:
  int fd_;
  bool socket_;
  int error_ = 0;
};

// The bytes already waiting on a descriptor, never blocking; without one (fd -1), never any.
class FdByteSource final : public ByteSource {
 public:
  explicit FdByteSource(int fd) : fd_(fd) {}
  std::optional<std::uint8_t> ReadByte() override;

 private:
  int fd_;
  std::array<std::uint8_t, 256> buffer_{};
  std::size_t at_ = 0;
  std::size_t size_ = 0;
};

// CLOCK_MONOTONIC: the bridge wait is real time on a host.
class SteadyMonotonicClock final : public MonotonicClock {
 public:
  std::int64_t NowNs() override;
};

// A host does not measure the step's work: work_cycles reads 0.
class NoCycleCounter final : public CycleCounter {
 public:
  std::uint32_t Cycles() override { return 0; }
};

// The rig's link token for a DUT that dials it over TCP: 32 hex digits read from `token_file`
// when one is given, else from the HILRIG_LINK_TOKEN environment variable (how the rig hands it
// to a program it starts). nullopt with `error` set when there is none or it is malformed; the
// error never repeats the text, which is a secret.
std::optional<std::array<std::uint8_t, 16>> LoadLinkToken(const std::string& token_file,
                                                          std::string& error);

// Makes SIGTERM and SIGINT set the returned process-wide flag (for ServeLine's `stop`), and
// SIGPIPE harmless (a write to a vanished peer is then an error value). Call once, from main.
const std::atomic<bool>* StopOnSignals();

enum class LineEnd {
  kStopped,       // `stop` was set
  kClosedIdle,    // the line closed between runs
  kClosedMidRun,  // the line closed while a run was going
  kReadFailed,    // reading the link line failed
  kWriteFailed,   // writing an answer failed (sink.error() says why)
};

// Feeds every byte of `link_fd` to the session until the line closes, a read or write fails, or
// `stop` (may be null) is set; looks at `stop` at least every 100 ms. A peer's Bye only ends a
// run: the session waits for the next Hello, as a board does.
LineEnd ServeLine(SerialDutSession& session, int link_fd, const FdLineSink& sink,
                  const std::atomic<bool>* stop);

}  // namespace hilrig::dut_link
