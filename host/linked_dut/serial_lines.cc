#include "host/linked_dut/serial_lines.h"

#include <time.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <set>

#include "host/link/child_process.h"
#include "host/link/open_byte_stream.h"
#include "rig/can_open.h"
#include "rig/clock.h"

namespace hilrig::host {
namespace {

constexpr const char* kSerialScheme = "serial:";
constexpr int kConnectAttemptMs = 100;
// A byte from the host to QEMU's STM32 USART over a TCP chardev: about 110 us, measured with an
// echo image (the emulated USART paces its receive side).
constexpr double kQemuByteTimeS = 110e-6;
constexpr double kBitsPerSerialByte = 10;  // 8N1: start, 8 data, stop

// Connects to the emulator's chardev on `port`, retrying while it is still starting up.
rig::Result<std::unique_ptr<ByteStream>> ConnectChardev(ChildProcess& qemu, std::uint16_t port,
                                                        const char* usart, std::int64_t deadline_ns,
                                                        const rig::Clock& clock) {
  const timespec nap{0, 20'000'000};
  while (true) {
    auto stream = ConnectTcpStream("127.0.0.1", port, kConnectAttemptMs);
    if (stream) return stream;
    if (auto exit = qemu.PollExit()) {
      return rig::MakeError("qemu-system-arm " + *exit + " before opening " + usart +
                            " (its own message is above)");
    }
    if (clock.NowNs() >= deadline_ns) {
      return rig::MakeError(rig::ErrorCode::kTimeout, std::string("qemu-system-arm's ") + usart +
                                                          " chardev: " + stream.error().message);
    }
    ::nanosleep(&nap, nullptr);
  }
}

}  // namespace

rig::Result<SerialPortSpec> ParseSerialPortSpec(const std::string& spec) {
  const std::string scheme = kSerialScheme;
  const auto bad = [&spec](const std::string& why) {
    return rig::MakeError("\"" + spec + "\": " + why);
  };
  if (spec.rfind(scheme, 0) != 0) {
    return bad("expected serial:DEVICE[,baud=N][,bridge=DEVICE][,bridge_baud=N]");
  }
  SerialPortSpec parsed;
  std::set<std::string> seen;
  std::size_t start = scheme.size();
  for (bool first = true; start <= spec.size(); first = false) {
    const std::size_t end = std::min(spec.find(',', start), spec.size());
    const std::string part = spec.substr(start, end - start);
    start = end + 1;
    if (first) {
      if (part.empty()) return bad("no device after serial:");
      parsed.device = part;
      continue;
    }
    const std::size_t equals = part.find('=');
    const std::string key = part.substr(0, equals);
    const std::string value = equals == std::string::npos ? "" : part.substr(equals + 1);
    if (key != "baud" && key != "bridge" && key != "bridge_baud") {
      return bad("unknown option \"" + part +
                 "\" (expected baud=N, bridge=DEVICE or bridge_baud=N)");
    }
    if (!seen.insert(key).second) return bad(key + "= given twice");
    if (key == "bridge") {
      if (value.empty()) return bad("no device after bridge=");
      parsed.bridge_device = value;
      continue;
    }
    auto baud = ParseBaud(value);
    if (!baud) return bad(baud.error().message);
    (key == "baud" ? parsed.baud : parsed.bridge_baud) = baud.value();
  }
  if (parsed.bridge_device == parsed.device) return bad("the bridge is the link's own device");
  return parsed;
}

SerialLineOpener SerialPortLines(const SerialPortSpec& spec) {
  return [spec](double) -> rig::Result<SerialLines> {
    SerialLines lines;
    auto link = OpenSerialPort(spec.device, spec.baud);
    if (!link) return link.error();
    lines.link = std::move(link).value();
    if (!spec.bridge_device.empty()) {
      auto bridge = OpenSerialPort(spec.bridge_device, spec.bridge_baud);
      if (!bridge) return bridge.error();
      lines.bridge = std::move(bridge).value();
    }
    if (!spec.can_uri.empty()) {
      auto can = rig::OpenCanBus(spec.can_uri);
      if (!can) return rig::MakeError("the dut's CAN bus: " + can.error().message);
      lines.can = std::move(can).value();
      lines.can_uri = spec.can_uri;
    }
    lines.description = "a board on " + lines.link->name();
    lines.byte_time_s = kBitsPerSerialByte / spec.baud;
    return lines;
  };
}

rig::Result<std::string> FindTargetImage(const std::optional<std::string>& explicit_path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (explicit_path) {
    if (fs::is_regular_file(*explicit_path, error)) return *explicit_path;
    return rig::MakeError("no target image at " + *explicit_path +
                          (error ? " (" + error.message() + ")" : ""));
  }
  auto directory = ExecutableDirectory();
  if (!directory) return directory.error();
  const fs::path exe_dir = directory.value();
  const std::vector<fs::path> candidates = {
      exe_dir.parent_path().parent_path() / "build-target" / kTargetImageName,
      exe_dir / kTargetImageName};
  std::string looked;
  for (const fs::path& candidate : candidates) {
    if (fs::is_regular_file(candidate, error)) return candidate.lexically_normal().string();
    looked += (looked.empty() ? "" : ", ") + candidate.lexically_normal().string();
  }
  return rig::MakeError("no target image (looked at " + looked +
                        "): run ./scripts/build-target, or name one with --target-image ELF");
}

SerialLineOpener QemuLines(const QemuTarget& target) {
  return [target](double timeout_s) -> rig::Result<SerialLines> {
    std::string qemu_path = target.qemu_path;
    if (qemu_path.empty()) {
      auto found = FindInPath("qemu-system-arm");
      if (!found)
        return rig::MakeError(found.error().message + " (apt-get install qemu-system-arm)");
      qemu_path = found.value();
    }
    auto link_port = FreeLoopbackPort();
    if (!link_port) return link_port.error();
    auto bridge_port = FreeLoopbackPort();
    if (!bridge_port) return bridge_port.error();
    if (bridge_port.value() == link_port.value()) {
      bridge_port = FreeLoopbackPort();
      if (!bridge_port) return bridge_port.error();
    }
    const auto chardev = [](std::uint16_t port) {
      return "tcp:127.0.0.1:" + std::to_string(port) + ",server=on,wait=off,nodelay=on";
    };
    auto qemu =
        ChildProcess::Spawn({qemu_path, "-M", "netduinoplus2", "-display", "none", "-monitor",
                             "none", "-icount", "shift=0", "-kernel", target.image_path, "-serial",
                             chardev(link_port.value()), "-serial", chardev(bridge_port.value())});
    if (!qemu) return qemu.error();
    // Starting the emulator takes wall time by nature.
    const rig::SteadyClock clock;
    const std::int64_t deadline_ns = clock.NowNs() + rig::NsFromSeconds(timeout_s);
    // QEMU waits for USART1's client before it opens USART2.
    auto link = ConnectChardev(qemu.value(), link_port.value(), "USART1", deadline_ns, clock);
    if (!link) return link.error();
    auto bridge = ConnectChardev(qemu.value(), bridge_port.value(), "USART2", deadline_ns, clock);
    if (!bridge) return bridge.error();
    SerialLines lines;
    lines.link = std::move(link).value();
    lines.bridge = std::move(bridge).value();
    lines.description = target.image_path + " on qemu-system-arm netduinoplus2 (pid " +
                        std::to_string(qemu.value().pid()) + ", virtual time)";
    lines.emulator = std::move(qemu).value();
    lines.byte_time_s = kQemuByteTimeS;
    return lines;
  };
}

}  // namespace hilrig::host
