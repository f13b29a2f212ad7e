#include "host/linked_dut/dialed_lines.h"

#include <cmath>
#include <memory>
#include <utility>

#include "host/link/child_process.h"
#include "host/link/hil_link_socket.h"
#include "host/link/link_token.h"
#include "host/linked_dut/peer_wait.h"
#include "rig/clock.h"

namespace hilrig::host {
namespace {

constexpr int kPortAttempts = 8;  // free link ports tried until the one above is free too

struct Listeners {
  std::unique_ptr<LinkListener> link;
  std::unique_ptr<LinkListener> bridge;
};

// Listens on port and port + 1; port 0: on a free pair.
rig::Result<Listeners> ListenOnPair(const std::string& address, std::uint16_t port) {
  rig::Error last = rig::MakeError("no free pair of ports");
  for (int attempt = 0; attempt < (port == 0 ? kPortAttempts : 1); ++attempt) {
    auto link = LinkListener::Listen(address, port);
    if (!link) return link.error();
    const std::uint16_t bridge_port = std::uint16_t(link.value()->port() + 1);
    auto bridge = LinkListener::Listen(address, bridge_port);
    if (bridge) return Listeners{std::move(link).value(), std::move(bridge).value()};
    last = bridge.error();
  }
  return last;
}

// Waits for one connection on `listener` until `deadline_ns`, watching the program and the stop
// request.
rig::Result<LinkListener::AcceptedStream> AcceptWithin(LinkListener& listener, const char* line,
                                                       std::optional<ChildProcess>& program,
                                                       const DialedLineSpec& spec,
                                                       std::int64_t deadline_ns,
                                                       const rig::Clock& clock) {
  const PeerWait wait{&clock, deadline_ns, program ? &*program : nullptr, spec.stop_requested};
  return WaitForPeer(
      wait,
      [&](int slice_ms) -> std::optional<rig::Result<LinkListener::AcceptedStream>> {
        auto accepted = listener.AcceptStream(slice_ms);
        if (!accepted && accepted.error().code == rig::ErrorCode::kTimeout) return std::nullopt;
        return accepted;
      },
      [&](const PeerWaitFailure& failure) -> rig::Result<LinkListener::AcceptedStream> {
        switch (failure.end) {
          case PeerWaitEnd::kStopped:
            return rig::MakeError(rig::ErrorCode::kInterrupted,
                                  std::string("stopped while waiting for the DUT's ") + line);
          case PeerWaitEnd::kPeerExited:
            return rig::MakeError(*spec.program + " " + failure.exit + " before it dialled the " +
                                  line + " (its own message is above)");
          case PeerWaitEnd::kTimedOut:
            break;
        }
        return rig::MakeError(rig::ErrorCode::kTimeout,
                              std::string("no DUT dialled the ") + line + " on " + spec.address +
                                  ":" + std::to_string(listener.port()) + " in time");
      });
}

// The token the DUT proves and, for a program the rig starts, the program running.
rig::Result<LinkToken> StartDut(const DialedLineSpec& spec, std::uint16_t port,
                                std::optional<ChildProcess>& program) {
  if (!spec.program) {
    bool created = false;
    auto token = ReadOrCreateLinkTokenFile(spec.token_file, &created);
    if (!token) return token.error();
    if (spec.notes != nullptr) {
      *spec.notes << "hilrig: waiting for the DUT: start it with --connect " << spec.address << ":"
                  << port << " --token-file " << spec.token_file
                  << (created ? " (a new token)" : "") << std::endl;
    }
    return token;
  }
  std::string path = *spec.program;
  if (path.find('/') == std::string::npos) {
    auto found = FindInPath(path);
    if (!found) return found.error();
    path = found.value();
  }
  auto token = NewLinkToken();
  if (!token) return token.error();
  std::vector<std::string> argv = {path};
  argv.insert(argv.end(), spec.program_args.begin(), spec.program_args.end());
  argv.insert(argv.end(), {"--connect", "127.0.0.1:" + std::to_string(port)});
  auto child =
      ChildProcess::Spawn(argv, {std::string(kLinkTokenEnvironment) + "=" + token.value().Hex()});
  if (!child) return child.error();
  program = std::move(child).value();
  return token;
}

}  // namespace

SerialLineOpener DialedLines(const DialedLineSpec& spec) {
  return [spec](double timeout_s) -> rig::Result<SerialLines> {
    auto listeners = ListenOnPair(spec.program ? "127.0.0.1" : spec.address, spec.port);
    if (!listeners) return listeners.error();
    std::optional<ChildProcess> program;
    auto token = StartDut(spec, listeners.value().link->port(), program);
    if (!token) return token.error();
    // Wall time by nature: it bounds how long a program, or a person, takes to start the DUT.
    const rig::SteadyClock clock;
    const std::int64_t deadline_ns = clock.NowNs() + rig::NsFromSeconds(timeout_s);
    auto link = AcceptWithin(*listeners.value().link, "link", program, spec, deadline_ns, clock);
    if (!link) return link.error();
    auto bridge =
        AcceptWithin(*listeners.value().bridge, "bridge", program, spec, deadline_ns, clock);
    if (!bridge) return bridge.error();
    SerialLines lines;
    lines.description =
        (spec.program ? *spec.program + " (pid " + std::to_string(program->pid()) + ")"
                      : std::string("a DUT")) +
        " dialled in from " + link.value().peer;
    lines.link = std::move(link.value().stream);
    lines.bridge = std::move(bridge.value().stream);
    lines.emulator = std::move(program);
    lines.link_token = token.value();
    return lines;
  };
}

}  // namespace hilrig::host
