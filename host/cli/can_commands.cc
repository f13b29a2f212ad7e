#include "host/cli/can_commands.h"

#include <cstdint>
#include <limits>
#include <memory>

#include "host/cli/cli.h"
#include "rig/can_open.h"
#include "rig/candump_log.h"
#include "rig/clock.h"

namespace hilrig::host {
namespace {

// How long an idle bus is left before it is polled again: far below a frame's time on a 1 Mbit/s
// bus would waste a core, far above it would make the output stutter.
constexpr std::int64_t kIdlePollNs = 1'000'000;

struct ListenOptions {
  std::string uri;
  int max_frames = std::numeric_limits<int>::max();
};

rig::Result<ListenOptions> ParseListenOptions(const std::vector<std::string>& args) {
  auto parsed = ParseCliArgs(args, {"--can", "--frames"});
  if (!parsed) return parsed.error();
  const CliArgs& cli = parsed.value();
  if (!cli.positional.empty()) return rig::MakeError("unexpected argument " + cli.positional[0]);
  ListenOptions options;
  const std::string* uri = cli.Option("--can");
  if (uri == nullptr) return rig::MakeError("--can URI is required");
  options.uri = *uri;
  if (const std::string* frames = cli.Option("--frames")) {
    auto count = ParseWholeNumberOption("--frames", *frames, 1, std::numeric_limits<int>::max());
    if (!count) return count.error();
    options.max_frames = count.value();
  }
  return options;
}

// The interface column of the printed lines: the SocketCAN interface, else the URI's scheme (a
// candump interface name holds no ':').
std::string InterfaceName(const std::string& uri) {
  auto parsed = rig::ParseCanBusUri(uri);
  if (parsed && parsed.value().scheme == rig::CanBusUri::Scheme::kSocketCan) {
    return parsed.value().interface;
  }
  return uri.substr(0, uri.find(':'));
}

bool StopRequested(const CliStreams& io) {
  return io.stop_requested != nullptr && io.stop_requested->load();
}

}  // namespace

int ListenCommand(const std::vector<std::string>& args, const CliStreams& io) {
  auto options = ParseListenOptions(args);
  if (!options) {
    io.err << "hilrig listen: " << options.error().message << "\n";
    return kExitBadInput;
  }
  auto bus = rig::OpenCanBus(options.value().uri);
  if (!bus) {
    io.err << "hilrig listen: " << bus.error().message << "\n";
    return kExitBadInput;
  }
  const std::string interface_name = InterfaceName(options.value().uri);
  const rig::SteadyClock clock;
  std::vector<rig::TimedCanFrame> frames;
  int printed = 0;
  while (printed < options.value().max_frames && !StopRequested(io)) {
    frames.clear();
    const std::int64_t now_ns = clock.NowNs();
    if (bus.value()->Receive(now_ns, frames) == 0) {
      clock.SleepUntilNs(now_ns + kIdlePollNs);
      continue;
    }
    for (const rig::TimedCanFrame& frame : frames) {
      if (printed == options.value().max_frames) break;
      io.out << rig::FormatCandumpLine(frame, interface_name) << "\n";
      ++printed;
    }
    io.out.flush();
  }
  return printed == options.value().max_frames ? kExitPass : kExitCheckFailed;
}

}  // namespace hilrig::host
