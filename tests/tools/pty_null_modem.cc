// pty_null_modem: a null-modem cable between two pairs of pseudo-terminals, for tests that run
// `hilrig run --dut serial:` against `dut_emu --serial` without a board. Two lines, the HIL link
// and the sensor bridge, each a pair of pseudo-terminals whose masters this program joins; the
// host side and the DUT side open the slaves. On the link line it damages the byte stream the way
// a noisy UART does, in either direction, from a seeded generator: a byte dropped, a bit flipped,
// a random byte inserted, each at a rate per byte or at given byte offsets of that direction's
// stream. It prints the four slave paths and "ready", and on SIGTERM or SIGINT what it relayed and
// injected, then exits 0.
//
//   pty_null_modem [--seed N] [--drop RATE] [--flip RATE] [--insert RATE]
//                  [--drop-at I,J,..] [--flip-at I,..] [--insert-at I,..]
//                  [--from-byte N] [--direction both|to-dut|to-host] [--mark-at N]
//
// --from-byte: the rates apply from this offset of each direction's stream on (the offsets of the
// *-at lists count from the stream's start regardless). --mark-at: prints "mark" once the link
// has carried N bytes to the DUT, for a test that acts in the middle of a run.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/signalfd.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "rig/command_args.h"

namespace {

constexpr int kExitUsage = 2;
constexpr int kExitFailed = 1;

struct FaultPlan {
  double drop_rate = 0;
  double flip_rate = 0;
  double insert_rate = 0;
  std::set<std::uint64_t> drop_at;
  std::set<std::uint64_t> flip_at;
  std::set<std::uint64_t> insert_at;
  std::uint64_t from_byte = 0;
};

constexpr std::uint64_t kNoMark = ~std::uint64_t{0};

struct Counts {
  std::uint64_t bytes = 0;  // read from the sending side
  std::uint64_t dropped = 0;
  std::uint64_t flipped = 0;
  std::uint64_t inserted = 0;
};

// One direction of one line: what the sending side wrote, damaged or not, on its way to the
// receiving side. Reading stops while the receiver has not taken what is pending.
class Direction {
 public:
  Direction(std::string name, int from_fd, int to_fd, const FaultPlan* plan, std::uint64_t seed)
      : name_(std::move(name)), from_fd_(from_fd), to_fd_(to_fd), plan_(plan), random_(seed) {}

  int from_fd() const { return from_fd_; }
  int to_fd() const { return to_fd_; }
  bool pending() const { return !pending_.empty(); }
  std::uint64_t bytes() const { return counts_.bytes; }

  // False when the sending side failed.
  bool Read() {
    std::array<std::uint8_t, 4096> chunk;
    const ssize_t got = ::read(from_fd_, chunk.data(), chunk.size());
    if (got < 0 && (errno == EAGAIN || errno == EINTR)) return true;
    if (got <= 0) return false;
    for (ssize_t i = 0; i < got; ++i) Pass(chunk[std::size_t(i)]);
    return true;
  }

  // False when the receiving side failed.
  bool Write() {
    const ssize_t written = ::write(to_fd_, pending_.data(), pending_.size());
    if (written < 0) return errno == EAGAIN || errno == EINTR;
    pending_.erase(pending_.begin(), pending_.begin() + written);
    return true;
  }

  void PrintCounts(std::ostream& out) const {
    out << name_ << " bytes=" << counts_.bytes << " dropped=" << counts_.dropped
        << " flipped=" << counts_.flipped << " inserted=" << counts_.inserted << "\n";
  }

 private:
  bool Due(double rate, const std::set<std::uint64_t>& at, std::uint64_t offset) {
    // Always draw, so one fault kind's rate does not shift the others' draws.
    const bool drawn = Uniform() < rate && offset >= plan_->from_byte;
    return drawn || at.contains(offset);
  }
  double Uniform() { return double(random_() >> 11) * 0x1.0p-53; }

  void Pass(std::uint8_t byte) {
    const std::uint64_t offset = counts_.bytes++;
    if (plan_ == nullptr) {
      pending_.push_back(byte);
      return;
    }
    const bool drop = Due(plan_->drop_rate, plan_->drop_at, offset);
    const bool flip = Due(plan_->flip_rate, plan_->flip_at, offset);
    const bool insert = Due(plan_->insert_rate, plan_->insert_at, offset);
    const auto bit = static_cast<unsigned>(random_() % 8);
    const auto extra = static_cast<std::uint8_t>(random_());
    if (drop) {
      ++counts_.dropped;
    } else {
      if (flip) ++counts_.flipped;
      pending_.push_back(flip ? std::uint8_t(byte ^ (1u << bit)) : byte);
    }
    if (insert) {
      ++counts_.inserted;
      pending_.push_back(extra);
    }
  }

  std::string name_;
  int from_fd_;
  int to_fd_;
  const FaultPlan* plan_;  // null: relayed as it is
  std::mt19937_64 random_;
  Counts counts_;
  std::vector<std::uint8_t> pending_;
};

// A pseudo-terminal pair in raw mode; both ends stay open here, so a side that closes its slave
// leaves the line silent, as a board that stops talking does, rather than hung up.
struct Pty {
  int master = -1;
  int slave = -1;
  std::string slave_path;
};

bool OpenPty(Pty& pty) {
  pty.master = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK);
  if (pty.master < 0 || ::grantpt(pty.master) != 0 || ::unlockpt(pty.master) != 0) return false;
  pty.slave_path = ::ptsname(pty.master);
  pty.slave = ::open(pty.slave_path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  termios mode{};
  if (pty.slave < 0 || ::tcgetattr(pty.slave, &mode) != 0) return false;
  ::cfmakeraw(&mode);
  return ::tcsetattr(pty.slave, TCSANOW, &mode) == 0;
}

hilrig::rig::Result<std::set<std::uint64_t>> ParseOffsets(const std::string& text,
                                                          const std::string& what) {
  std::set<std::uint64_t> offsets;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    auto offset = hilrig::rig::ParseNumber<std::uint64_t>(text.substr(start, comma - start), what);
    if (!offset) return offset.error();
    offsets.insert(offset.value());
    start = comma + 1;
  }
  return offsets;
}

hilrig::rig::Result<double> ParseRate(const std::string& text, const std::string& what) {
  auto rate = hilrig::rig::ParseNumber<double>(text, what);
  if (rate && !(rate.value() >= 0 && rate.value() <= 1)) {
    return hilrig::rig::MakeError(what + " " + text + ": not a rate in 0..1");
  }
  return rate;
}

struct Options {
  FaultPlan plan;
  std::uint64_t seed = 1;
  bool to_dut = true;
  bool to_host = true;
  std::uint64_t mark_at = kNoMark;
};

hilrig::rig::Result<Options> ParseOptions(const std::vector<std::string>& args) {
  auto cli = hilrig::rig::ParseCliArgs(
      args, {"--seed", "--drop", "--flip", "--insert", "--drop-at", "--flip-at", "--insert-at",
             "--from-byte", "--direction", "--mark-at"});
  if (!cli) return cli.error();
  if (!cli.value().positional.empty()) {
    return hilrig::rig::MakeError("unexpected argument " + cli.value().positional.front());
  }
  Options options;
  for (const auto& [name, value] : cli.value().options) {
    hilrig::rig::Result<void> parsed;
    const auto rate = [&](double& out) {
      auto number = ParseRate(value, name);
      if (number) out = number.value();
      return number ? hilrig::rig::Result<void>() : number.error();
    };
    const auto offsets = [&](std::set<std::uint64_t>& out) {
      auto list = ParseOffsets(value, name);
      if (list) out = list.value();
      return list ? hilrig::rig::Result<void>() : list.error();
    };
    const auto whole = [&](std::uint64_t& out) {
      auto number = hilrig::rig::ParseNumber<std::uint64_t>(value, name);
      if (number) out = number.value();
      return number ? hilrig::rig::Result<void>() : number.error();
    };
    if (name == "--seed") parsed = whole(options.seed);
    if (name == "--drop") parsed = rate(options.plan.drop_rate);
    if (name == "--flip") parsed = rate(options.plan.flip_rate);
    if (name == "--insert") parsed = rate(options.plan.insert_rate);
    if (name == "--drop-at") parsed = offsets(options.plan.drop_at);
    if (name == "--flip-at") parsed = offsets(options.plan.flip_at);
    if (name == "--insert-at") parsed = offsets(options.plan.insert_at);
    if (name == "--from-byte") parsed = whole(options.plan.from_byte);
    if (name == "--mark-at") parsed = whole(options.mark_at);
    if (name == "--direction") {
      if (value != "both" && value != "to-dut" && value != "to-host") {
        return hilrig::rig::MakeError("--direction " + value +
                                      ": expected both, to-dut or to-host");
      }
      options.to_dut = value != "to-host";
      options.to_host = value != "to-dut";
    }
    if (!parsed) return parsed.error();
  }
  return options;
}

// Relays until a stop signal arrives on `signals`; returns the exit code. `mark_at` counts the
// bytes of `link_to_dut`.
int Relay(std::vector<Direction>& directions, const Direction& link_to_dut, int signals,
          std::uint64_t mark_at) {
  while (true) {
    if (link_to_dut.bytes() >= mark_at) {
      std::cout << "mark" << std::endl;
      mark_at = kNoMark;
    }
    std::vector<pollfd> fds{{signals, POLLIN, 0}};
    for (const Direction& direction : directions) {
      // A direction with bytes pending waits for its receiver before it reads more.
      fds.push_back(direction.pending() ? pollfd{direction.to_fd(), POLLOUT, 0}
                                        : pollfd{direction.from_fd(), POLLIN, 0});
    }
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      std::cerr << "pty_null_modem: poll: " << std::strerror(errno) << "\n";
      return kExitFailed;
    }
    if (fds[0].revents != 0) return 0;
    for (std::size_t i = 0; i < directions.size(); ++i) {
      Direction& direction = directions[i];
      const short events = fds[i + 1].revents;
      if (events == 0) continue;
      const bool ok = direction.pending() ? direction.Write() : direction.Read();
      if (!ok) {
        std::cerr << "pty_null_modem: a pseudo-terminal failed: " << std::strerror(errno) << "\n";
        return kExitFailed;
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  auto options = ParseOptions(std::vector<std::string>(argv, argv + argc));
  if (!options) {
    std::cerr << "pty_null_modem: " << options.error().message << "\n";
    return kExitUsage;
  }
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGTERM);
  sigaddset(&stop, SIGINT);
  ::sigprocmask(SIG_BLOCK, &stop, nullptr);
  const int signals = ::signalfd(-1, &stop, SFD_CLOEXEC);
  std::array<Pty, 4> ptys;  // link host, link dut, bridge host, bridge dut
  for (Pty& pty : ptys) {
    if (signals < 0 || !OpenPty(pty)) {
      std::cerr << "pty_null_modem: cannot open a pseudo-terminal: " << std::strerror(errno)
                << "\n";
      return kExitFailed;
    }
  }
  const FaultPlan& plan = options.value().plan;
  const std::uint64_t seed = options.value().seed;
  // The bridge first: a step's sensor bytes, written before the step, reach the DUT before it.
  std::vector<Direction> directions;
  directions.emplace_back("bridge_to_dut", ptys[2].master, ptys[3].master, nullptr, seed);
  directions.emplace_back("bridge_to_host", ptys[3].master, ptys[2].master, nullptr, seed);
  directions.emplace_back("link_to_dut", ptys[0].master, ptys[1].master,
                          options.value().to_dut ? &plan : nullptr, seed);
  directions.emplace_back("link_to_host", ptys[1].master, ptys[0].master,
                          options.value().to_host ? &plan : nullptr, seed + 1);
  std::cout << "link_host " << ptys[0].slave_path << "\nlink_dut " << ptys[1].slave_path
            << "\nbridge_host " << ptys[2].slave_path << "\nbridge_dut " << ptys[3].slave_path
            << "\nready" << std::endl;
  const int code = Relay(directions, directions[2], signals, options.value().mark_at);
  for (const Direction& direction : directions) direction.PrintCounts(std::cout);
  std::cout.flush();
  return code;
}
