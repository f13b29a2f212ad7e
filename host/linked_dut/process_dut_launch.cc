#include "host/linked_dut/process_dut_launch.h"

#include <cmath>

#include "host/link/dut_acceptor.h"
#include "host/link/link_token.h"
#include "host/link/shm_byte_stream.h"
#include "host/linked_dut/peer_wait.h"
#include "rig/can_open.h"
#include "rig/clock.h"
#include "rig/udp_bus.h"

namespace hilrig::host {
namespace {

// The address the child dials: the listening one, or loopback when listening on every address.
std::string DialAddress(const std::string& listen_address) {
  if (listen_address == "0.0.0.0") return "127.0.0.1";
  if (listen_address == "::") return "::1";
  return listen_address;
}

// Calls `poll(slice_ms)` until it yields a value, failing once the child exits or the start
// deadline passes; `step` names what the child was to do ("prove the link token").
template <typename Poll>
auto WatchChild(ChildProcess& child, int timeout_ms, const std::string& step, Poll poll)
    -> rig::Result<typename decltype(poll(0))::value_type> {
  using Value = typename decltype(poll(0))::value_type;
  // The start deadline is wall time by nature: it bounds how long the process may take.
  const rig::SteadyClock clock;
  const PeerWait wait{&clock, clock.NowNs() + std::int64_t{timeout_ms} * 1'000'000, &child};
  return WaitForPeer(
      wait,
      [&](int slice_ms) -> std::optional<rig::Result<Value>> {
        if (auto value = poll(slice_ms)) return rig::Result<Value>(std::move(*value));
        return std::nullopt;
      },
      [&](const PeerWaitFailure& failure) -> rig::Result<Value> {
        if (failure.end == PeerWaitEnd::kPeerExited) {
          return rig::MakeError("dut process " + failure.exit + " before it could " + step);
        }
        return rig::MakeError("the dut process did not " + step + " within " +
                              std::to_string(timeout_ms) + " ms");
      });
}

// The forwarder's end of the DUT's CAN bus, and the --can URI that gives dut_emu the other end.
struct ForwardBus {
  std::unique_ptr<rig::CanBus> bus;
  std::string dut_uri;
};

rig::Result<ForwardBus> OpenForwardBus(const ProcessDutOptions& options) {
  if (!options.can_uri.empty()) {
    auto bus = options.open_can_bus ? options.open_can_bus(options.can_uri)
                                    : rig::OpenCanBus(options.can_uri);
    if (!bus) return bus.error();
    return ForwardBus{std::move(bus).value(), options.can_uri};
  }
  // Node 0 of the UDP bus is the runner's forwarder; node 1's port is freed for the child.
  auto udp = rig::OpenUdpBusGroup(2);
  if (!udp) return rig::MakeError("UDP CAN bus for the dut: " + udp.error().message);
  const std::uint16_t base_port = udp.value()[0]->local_port();
  udp.value()[1].reset();
  return ForwardBus{std::move(udp.value()[0]), "udp:" + std::to_string(base_port) + ":1:2"};
}

// The child's command line: the program, a user's program's own arguments, the link's, then the
// test hooks.
std::vector<std::string> CommandLine(const std::string& path, const ProcessDutOptions& options,
                                     const std::vector<std::string>& link_args) {
  std::vector<std::string> argv = {path};
  argv.insert(argv.end(), options.program_args.begin(), options.program_args.end());
  argv.insert(argv.end(), link_args.begin(), link_args.end());
  argv.insert(argv.end(), options.extra_args.begin(), options.extra_args.end());
  return argv;
}

rig::Result<LaunchedDut> LaunchOverTcp(const std::string& path, const ProcessDutOptions& options) {
  auto listener = LinkListener::Listen(options.listen_address, 0);
  if (!listener) return listener.error();
  auto forward_bus = OpenForwardBus(options);
  if (!forward_bus) return forward_bus.error();
  auto token = NewLinkToken();
  if (!token) return token.error();
  const std::string link =
      DialAddress(options.listen_address) + ":" + std::to_string(listener.value()->port());
  auto child = ChildProcess::Spawn(
      CommandLine(path, options, {"--link", link, "--can", forward_bus.value().dut_uri}),
      {std::string(kLinkTokenEnvironment) + "=" + token.value().Hex()});
  if (!child) return child.error();
  DutAcceptor acceptor(*listener.value(), token.value());
  auto accepted =
      WatchChild(child.value(), CeilMilliseconds(options.start_timeout_s), "prove the link token",
                 [&](int slice_ms) { return acceptor.Poll(slice_ms); });
  if (!accepted) {
    acceptor.RefusePending();
    rig::Error error = accepted.error();
    if (acceptor.rejected_count() > 0) error.message += " (" + acceptor.RejectedSummary() + ")";
    return error;
  }
  return LaunchedDut{std::move(child).value(), std::move(accepted.value().link),
                     std::move(forward_bus.value().bus), acceptor.rejected_count(),
                     acceptor.RejectedSummary()};
}

// The bus of a DUT that dials in: can_uri, or the loopback UDP bus at listen_port + 1 whose node
// 1 is the DUT's, so that the user can start the DUT with a --can known before the run.
rig::Result<ForwardBus> OpenListeningBus(const ProcessDutOptions& options) {
  if (!options.can_uri.empty()) return OpenForwardBus(options);
  const std::string base = "udp:" + std::to_string(options.listen_port + 1);
  auto bus = rig::OpenCanBus(base + ":0:2");
  if (!bus) return rig::MakeError("UDP CAN bus for the dut: " + bus.error().message);
  return ForwardBus{std::move(bus).value(), base + ":1:2"};
}

rig::Result<LaunchedDut> LaunchByListening(const ProcessDutOptions& options) {
  bool created = false;
  auto token = ReadOrCreateLinkTokenFile(options.token_file, &created);
  if (!token) return token.error();
  auto listener = LinkListener::Listen(options.listen_address, options.listen_port);
  if (!listener) return listener.error();
  auto forward_bus = OpenListeningBus(options);
  if (!forward_bus) return forward_bus.error();
  const int timeout_ms = CeilMilliseconds(options.start_timeout_s);
  if (options.notes != nullptr) {
    *options.notes << "hilrig: waiting up to " << timeout_ms / 1000 << " s for the DUT: start it "
                   << "with --link " << ListenEndpoint(options) << " --can "
                   << forward_bus.value().dut_uri << " --token-file " << options.token_file
                   << (created ? " (a new token)" : "") << std::endl;
  }
  DutAcceptor acceptor(*listener.value(), token.value());
  // Wall time by nature: it bounds how long a person may take to start a program.
  const rig::SteadyClock clock;
  const PeerWait wait{&clock, clock.NowNs() + std::int64_t{timeout_ms} * 1'000'000, nullptr,
                      options.stop_requested};
  return WaitForPeer(
      wait,
      [&](int slice_ms) -> std::optional<rig::Result<LaunchedDut>> {
        auto accepted = acceptor.Poll(slice_ms);
        if (!accepted) return std::nullopt;
        return rig::Result<LaunchedDut>(
            LaunchedDut{std::nullopt, std::move(accepted->link), std::move(forward_bus.value().bus),
                        acceptor.rejected_count(), acceptor.RejectedSummary()});
      },
      [&](const PeerWaitFailure& failure) -> rig::Result<LaunchedDut> {
        acceptor.RefusePending();
        if (failure.end == PeerWaitEnd::kStopped) {
          return rig::MakeError(rig::ErrorCode::kInterrupted,
                                "stopped while waiting for a DUT on " + ListenEndpoint(options));
        }
        std::string message = "no DUT dialled " + ListenEndpoint(options) + " with the token of " +
                              options.token_file + " within " + std::to_string(timeout_ms) + " ms";
        if (acceptor.rejected_count() > 0) message += " (" + acceptor.RejectedSummary() + ")";
        return rig::MakeError(rig::ErrorCode::kTimeout, message);
      });
}

rig::Result<LaunchedDut> LaunchOverShm(const std::string& path, const ProcessDutOptions& options) {
  auto stream = ShmByteStream::Create();
  if (!stream) return stream.error();
  const int fd = stream.value()->shared_fd();
  std::vector<std::string> link_args = {"--link-shm", std::to_string(fd)};
  std::unique_ptr<rig::CanBus> forward_bus;
  if (!options.can_uri.empty()) {
    auto bus = OpenForwardBus(options);
    if (!bus) return bus.error();
    forward_bus = std::move(bus.value().bus);
    link_args.insert(link_args.end(), {"--can", options.can_uri});
  }
  auto child = ChildProcess::Spawn(CommandLine(path, options, link_args), {}, {fd});
  if (!child) return child.error();
  auto link = std::make_unique<LinkConnection>(std::move(stream).value(), "dut_emu (shm)");
  auto hello = WatchChild(child.value(), CeilMilliseconds(options.start_timeout_s),
                          "say hello on the shm link",
                          [&](int slice_ms) -> std::optional<proto::LinkMessage> {
                            LinkReceived received = link->Receive(slice_ms);
                            if (received.status == LinkReceiveStatus::kMessage)
                              return std::move(received.message);
                            return std::nullopt;
                          });
  if (!hello) return hello.error();
  if (!hello.value().has_hello() || hello.value().hello().role() != proto::Hello::DUT) {
    return rig::MakeError("the dut process's first message on the shm link is not a dut hello");
  }
  return LaunchedDut{std::move(child).value(), std::move(link), std::move(forward_bus), 0, {}};
}

}  // namespace

rig::Result<LaunchedDut> LaunchDut(const std::string& dut_emu_path,
                                   const ProcessDutOptions& options) {
  if (options.listen) return LaunchByListening(options);
  switch (options.transport) {
    case DutLinkTransport::kSharedMemory:
      return LaunchOverShm(dut_emu_path, options);
    case DutLinkTransport::kTcp:
      return LaunchOverTcp(dut_emu_path, options);
  }
  return rig::MakeError("unknown dut link transport");
}

}  // namespace hilrig::host
