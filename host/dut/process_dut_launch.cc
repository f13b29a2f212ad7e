#include "host/dut/process_dut_launch.h"

#include <cmath>

#include "host/link/dut_acceptor.h"
#include "host/link/link_token.h"
#include "host/link/shm_byte_stream.h"
#include "rig/clock.h"
#include "rig/udp_bus.h"

namespace hilrig::host {
namespace {

constexpr int kPollSliceMs = 20;  // how often a waiting runner checks that the process lives

int Milliseconds(double seconds) { return static_cast<int>(std::ceil(seconds * 1000)); }

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
  // The start deadline is wall time by nature: it bounds how long the process may take.
  const rig::SteadyClock clock;
  const std::int64_t deadline_ns = clock.NowNs() + std::int64_t{timeout_ms} * 1'000'000;
  while (true) {
    if (auto value = poll(kPollSliceMs)) return std::move(*value);
    if (auto exit = child.PollExit()) {
      return rig::MakeError("dut process " + *exit + " before it could " + step);
    }
    if (clock.NowNs() >= deadline_ns) {
      return rig::MakeError("the dut process did not " + step + " within " +
                            std::to_string(timeout_ms) + " ms");
    }
  }
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

std::vector<std::string> WithExtraArgs(std::vector<std::string> argv,
                                       const ProcessDutOptions& options) {
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
      WithExtraArgs({path, "--link", link, "--can", forward_bus.value().dut_uri}, options),
      {std::string(kLinkTokenEnvironment) + "=" + token.value().Hex()});
  if (!child) return child.error();
  DutAcceptor acceptor(*listener.value(), token.value());
  auto accepted =
      WatchChild(child.value(), Milliseconds(options.start_timeout_s), "prove the link token",
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

rig::Result<LaunchedDut> LaunchOverShm(const std::string& path, const ProcessDutOptions& options) {
  auto stream = ShmByteStream::Create();
  if (!stream) return stream.error();
  const int fd = stream.value()->shared_fd();
  std::vector<std::string> argv = {path, "--link-shm", std::to_string(fd)};
  std::unique_ptr<rig::CanBus> forward_bus;
  if (!options.can_uri.empty()) {
    auto bus = OpenForwardBus(options);
    if (!bus) return bus.error();
    forward_bus = std::move(bus.value().bus);
    argv.insert(argv.end(), {"--can", options.can_uri});
  }
  auto child = ChildProcess::Spawn(WithExtraArgs(std::move(argv), options), {}, {fd});
  if (!child) return child.error();
  auto link = std::make_unique<LinkConnection>(std::move(stream).value(), "dut_emu (shm)");
  auto hello =
      WatchChild(child.value(), Milliseconds(options.start_timeout_s), "say hello on the shm link",
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
  switch (options.transport) {
    case DutLinkTransport::kSharedMemory:
      return LaunchOverShm(dut_emu_path, options);
    case DutLinkTransport::kTcp:
      return LaunchOverTcp(dut_emu_path, options);
  }
  return rig::MakeError("unknown dut link transport");
}

}  // namespace hilrig::host
