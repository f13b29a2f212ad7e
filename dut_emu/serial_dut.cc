#include "dut_emu/serial_dut.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "dut_emu/dut_emu_server.h"
#include "dut_fw/dut_core_controller.h"
#include "dut_link/posix/line_io.h"
#include "dut_link/serial_session.h"
#include "rig/command_args.h"

namespace hilrig::dut_emu {

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
      if (!dut_link::IsTermiosRate(baud.value())) {
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
  const dut_link::OwnedLine link = dut_link::OpenRawTty(options.link_path, options.baud);
  if (!link.ok()) {
    log << "dut_emu: " << link.error() << "\n";
    return kExitFailed;
  }
  dut_link::OwnedLine bridge;
  if (options.bridge_path) {
    bridge = dut_link::OpenRawTty(*options.bridge_path, options.bridge_baud);
    if (!bridge.ok()) {
      log << "dut_emu: " << bridge.error() << "\n";
      return kExitFailed;
    }
  }
  dut_link::FdLineSink sink(link.fd());
  dut_link::FdByteSource bridge_source(bridge.fd());
  dut_link::SteadyMonotonicClock clock;
  dut_link::NoCycleCounter cycles;
  const std::string name = "dut_emu " + std::to_string(::getpid());
  const dut_link::TargetDescription target{name, "host", 0, 0, 0, 0, {}};
  dut_fw::DutCoreController<float> controller;
  dut_link::SerialDutSession session(controller, sink, bridge_source, clock, cycles, target);
  switch (dut_link::ServeLine(session, link.fd(), sink, stop_requested)) {
    case dut_link::LineEnd::kStopped:
      return kExitOk;
    case dut_link::LineEnd::kClosedIdle:
      log << "dut_emu: the line " << options.link_path << " closed\n";
      return kExitOk;
    case dut_link::LineEnd::kClosedMidRun:
      log << "dut_emu: the line " << options.link_path << " closed\n";
      return kExitFailed;
    case dut_link::LineEnd::kReadFailed:
      log << "dut_emu: cannot read " << options.link_path << ": " << std::strerror(errno) << "\n";
      return kExitFailed;
    case dut_link::LineEnd::kWriteFailed:
      log << "dut_emu: cannot write to " << options.link_path << ": " << std::strerror(sink.error())
          << "\n";
      return kExitFailed;
  }
  return kExitFailed;
}

}  // namespace hilrig::dut_emu
