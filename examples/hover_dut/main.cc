// hover_dut: a DUT of a team's own (examples/hover_dut/hover_controller.h) on the rig's HIL link,
// through the DUT-side link library alone. It speaks the link on a serial line (a board's UART,
// a pseudo-terminal) or dials the rig over TCP, which is what `hilrig run --dut exec:hover_dut
// --dut-link line` and `--dut listen:ADDRESS:PORT --dut-link line` expect (docs/your-dut.md).
//
//   hover_dut --serial DEVICE[,bridge=DEVICE][,baud=N][,bridge_baud=N]
//   hover_dut --connect HOST:PORT [--token-file FILE]
//
// On TCP the link is PORT and the sensor bridge PORT+1, and the hello carries the rig's link token
// (--token-file, else HILRIG_LINK_TOKEN). Exit codes: 0 the line closed between runs or a signal
// stopped it, 1 the line failed or closed mid-run, 2 bad usage.
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "dut_link/posix/line_io.h"
#include "dut_link/serial_session.h"
#include "examples/hover_dut/hover_controller.h"

namespace {

namespace link = hilrig::dut_link;

constexpr int kUsage = 2;
constexpr int kConnectTimeoutMs = 10'000;
constexpr const char* kUsageText =
    "usage: hover_dut --serial DEVICE[,bridge=DEVICE][,baud=N][,bridge_baud=N]\n"
    "       hover_dut --connect HOST:PORT [--token-file FILE]\n";

struct Options {
  std::string device, bridge_device;
  std::uint32_t baud = 2'000'000, bridge_baud = 921'600;
  std::string host;
  std::uint16_t port = 0;
  std::string token_file;
};

std::optional<std::uint32_t> Number(const std::string& text, std::uint32_t max) {
  char* end = nullptr;
  errno = 0;
  const unsigned long value = std::strtoul(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || value > max) return std::nullopt;
  return std::uint32_t(value);
}

// "DEVICE[,bridge=DEVICE][,baud=N][,bridge_baud=N]"; false on anything else.
bool ParseSerial(const std::string& spec, Options& options) {
  std::size_t start = 0;
  for (bool first = true; start <= spec.size(); first = false) {
    const std::size_t comma = std::min(spec.find(',', start), spec.size());
    const std::string part = spec.substr(start, comma - start);
    start = comma + 1;
    const std::size_t equals = part.find('=');
    const std::string key = part.substr(0, equals);
    const std::string value = equals == std::string::npos ? "" : part.substr(equals + 1);
    if (first) {
      options.device = part;
    } else if (key == "bridge") {
      options.bridge_device = value;
    } else if (key == "baud" || key == "bridge_baud") {
      const auto rate = Number(value, 4'000'000);
      if (!rate) return false;
      (key == "baud" ? options.baud : options.bridge_baud) = *rate;
    } else {
      return false;
    }
  }
  return !options.device.empty();
}

bool ParseConnect(const std::string& endpoint, Options& options) {
  const std::size_t colon = endpoint.rfind(':');
  if (colon == std::string::npos || colon == 0) return false;
  const auto port = Number(endpoint.substr(colon + 1), 65534);
  if (!port || *port == 0) return false;
  options.host = endpoint.substr(0, colon);
  options.port = std::uint16_t(*port);
  return true;
}

std::optional<Options> Parse(const std::vector<std::string>& args) {
  Options options;
  for (std::size_t i = 1; i + 1 < args.size(); i += 2) {
    const std::string& key = args[i];
    const std::string& value = args[i + 1];
    const bool ok = key == "--serial"       ? ParseSerial(value, options)
                    : key == "--connect"    ? ParseConnect(value, options)
                    : key == "--token-file" ? (options.token_file = value, true)
                                            : false;
    if (!ok) return std::nullopt;
  }
  if (args.size() % 2 == 0 || options.device.empty() == options.host.empty()) return std::nullopt;
  return options;
}

// The link and bridge lines the options name.
bool OpenLines(const Options& options, link::OwnedLine& line, link::OwnedLine& bridge) {
  if (!options.device.empty()) {
    line = link::OpenRawTty(options.device, options.baud);
    if (line.ok() && !options.bridge_device.empty())
      bridge = link::OpenRawTty(options.bridge_device, options.bridge_baud);
  } else {
    line = link::ConnectTcpLine(options.host, options.port, kConnectTimeoutMs);
    if (line.ok()) bridge = link::ConnectTcpLine(options.host, options.port + 1, kConnectTimeoutMs);
  }
  const std::string& error = !line.ok() ? line.error() : bridge.error();
  if (error.empty()) return true;
  std::cerr << "hover_dut: " << error << "\n";
  return false;
}

int Serve(const Options& options, const std::array<std::uint8_t, 16>* token,
          const std::atomic<bool>* stop) {
  link::OwnedLine line, bridge;
  if (!OpenLines(options, line, bridge)) return 1;
  link::FdLineSink sink(line.fd());
  link::FdByteSource bridge_source(bridge.fd());
  link::SteadyMonotonicClock clock;
  link::NoCycleCounter cycles;
  link::TargetDescription target;
  target.name = "hover_dut example";
  target.board = "host";
  if (token != nullptr) target.link_token = *token;
  hilrig::examples::HoverController controller;
  link::SerialDutSession session(controller, sink, bridge_source, clock, cycles, target);
  switch (link::ServeLine(session, line.fd(), sink, stop)) {
    case link::LineEnd::kStopped:
    case link::LineEnd::kClosedIdle:
      return 0;
    case link::LineEnd::kClosedMidRun:
      std::cerr << "hover_dut: the line closed during a run\n";
      return 1;
    case link::LineEnd::kReadFailed:
    case link::LineEnd::kWriteFailed:
      std::cerr << "hover_dut: the line failed: " << std::strerror(errno) << "\n";
      return 1;
  }
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv, argv + argc);
  const std::optional<Options> options = Parse(args);
  if (!options) {
    // The arguments the rig gives a program on its process link, not this one's.
    for (const std::string& arg : args) {
      if (arg == "--link" || arg == "--link-shm") {
        std::cerr << "hover_dut: speaks the line link; start it with --dut exec:PROGRAM "
                     "--dut-link line\n";
      }
    }
    std::cerr << kUsageText;
    return kUsage;
  }
  std::optional<std::array<std::uint8_t, 16>> token;
  if (!options->host.empty()) {
    std::string error;
    token = link::LoadLinkToken(options->token_file, error);
    if (!token) {
      std::cerr << "hover_dut: " << error << "\n";
      return kUsage;
    }
  }
  ::unsetenv("HILRIG_LINK_TOKEN");  // nothing this process starts needs the secret
  return Serve(*options, token ? &*token : nullptr, link::StopOnSignals());
}
