#include "host/linked_dut/dut_choice.h"

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <utility>
#include <vector>

#include "host/dut/firmware_config.h"
#include "host/dut/in_process_dut.h"
#include "host/link/open_byte_stream.h"
#include "rig/clock.h"
#include "rig/command_args.h"

namespace hilrig::host {
namespace {

// QEMU's lines are loopback sockets that lose nothing, and an emulated core on a busy host can
// take long over a step: wait longer before repeating a step or giving up on it.
constexpr double kQemuAnswerTimeoutS = 10;
constexpr double kQemuStepRetryS = 1;
// A DUT that dials in is started by a person, once the run says where to dial.
constexpr double kListenStartTimeoutS = 60;
// PX4 SITL's simulator port and the port its offboard link sends to.
constexpr std::uint16_t kPx4SimulatorPort = 4560;
constexpr std::uint16_t kPx4ApiPort = 14540;

rig::Result<DutKind> ParseKind(const std::optional<std::string>& dut) {
  if (!dut || *dut == "inproc") return DutKind::kInProcess;
  if (*dut == "inproc-float") return DutKind::kInProcessFloat;
  if (*dut == "process") return DutKind::kProcess;
  if (dut->starts_with("exec:")) return DutKind::kExec;
  if (dut->starts_with("listen:")) return DutKind::kListen;
  if (*dut == "qemu") return DutKind::kQemu;
  if (dut->starts_with("serial:")) return DutKind::kSerial;
  if (*dut == "mavlink-emu") return DutKind::kMavlinkEmu;
  if (*dut == "px4-sitl" || dut->starts_with("px4-sitl:")) return DutKind::kPx4Sitl;
  if (*dut == "mavlink-emu-hitl") return DutKind::kMavlinkEmuHitl;
  if (dut->starts_with("px4-hitl:")) return DutKind::kPx4Hitl;
  return rig::MakeError("--dut \"" + *dut +
                        "\": expected inproc, inproc-float, process, exec:PROGRAM[,ARG...], "
                        "listen:ADDRESS:PORT[,token=FILE], qemu, "
                        "serial:DEVICE[,baud=N][,bridge=DEVICE][,bridge_baud=N], mavlink-emu, "
                        "px4-sitl[:PORT], mavlink-emu-hitl or px4-hitl:DEVICE[,baud=N]");
}

// A process the rig talks to over the HIL link: dut_emu, a user's program it starts, or one that
// dials in.
bool AProcess(DutKind kind) {
  return kind == DutKind::kProcess || kind == DutKind::kExec || kind == DutKind::kListen;
}

// A flight stack on a board, in real time.
bool OnABoard(DutKind kind) {
  return kind == DutKind::kMavlinkEmuHitl || kind == DutKind::kPx4Hitl;
}

bool OverMavlink(DutKind kind) {
  return kind == DutKind::kMavlinkEmu || kind == DutKind::kPx4Sitl || OnABoard(kind);
}

bool OverALink(DutKind kind) {
  return AProcess(kind) || kind == DutKind::kQemu || kind == DutKind::kSerial || OverMavlink(kind);
}

// Which options go with which kind; the first one that does not fit is the error.
rig::Result<void> CheckOptionsFit(DutKind kind, const DutArguments& arguments) {
  if (arguments.target_image && kind != DutKind::kQemu) {
    return rig::MakeError("--target-image needs --dut qemu");
  }
  if (arguments.timeout_s && !OverALink(kind)) {
    return rig::MakeError(
        "--dut-timeout-s needs --dut process, exec:, listen:, qemu, serial:, mavlink-emu, "
        "px4-sitl, mavlink-emu-hitl or px4-hitl:");
  }
  const bool line = arguments.link && *arguments.link == "line";
  if (arguments.link && !line && (!AProcess(kind) || kind == DutKind::kListen)) {
    return rig::MakeError("--dut-link needs --dut process or exec:");
  }
  if (line && kind != DutKind::kExec && kind != DutKind::kListen) {
    return rig::MakeError("--dut-link line needs --dut exec: or listen:");
  }
  if (arguments.link && *arguments.link != "shm" && *arguments.link != "tcp" && !line) {
    return rig::MakeError("--dut-link \"" + *arguments.link + "\": expected shm, tcp or line");
  }
  // On the line link the tactile frames ride the bridge line: no bus reaches the DUT.
  if (arguments.can && line) return rig::MakeError("--can does not go with --dut-link line");
  // The in-process DUT sits on the runner's emulated bus, and QEMU's board has no CAN port: only
  // a DUT process or a board reaches another bus.
  if (arguments.can && !AProcess(kind) && kind != DutKind::kSerial) {
    return rig::MakeError("--can " + *arguments.can + " needs --dut process, exec: or serial:");
  }
  return {};
}

// --dut-timeout-s S, if given; `fallback` otherwise.
rig::Result<double> ParseTimeout(const std::optional<std::string>& timeout, double fallback) {
  if (!timeout) return fallback;
  char* end = nullptr;
  const double seconds = std::strtod(timeout->c_str(), &end);
  if (timeout->empty() || *end != '\0') {
    return rig::MakeError("--dut-timeout-s \"" + *timeout + "\" is not a number");
  }
  return seconds;
}

rig::Result<void> ParseSerialOptions(const DutArguments& arguments, DutChoice& choice) {
  SerialDutOptions& options = choice.serial;
  if (choice.kind == DutKind::kQemu) {
    options.answer_timeout_s = kQemuAnswerTimeoutS;
    options.step_retry_s = kQemuStepRetryS;
    choice.target_image = arguments.target_image;
  }
  auto seconds = ParseTimeout(arguments.timeout_s, options.answer_timeout_s);
  if (!seconds) return seconds.error();
  options.answer_timeout_s = seconds.value();
  // A short watchdog still leaves room for a retry before it gives up.
  options.step_retry_s = std::min(options.step_retry_s, options.answer_timeout_s / 2);
  if (auto valid = ValidateSerialDutOptions(options); !valid) {
    return rig::MakeError("--dut-timeout-s: " + valid.error().message);
  }
  if (choice.kind == DutKind::kSerial) {
    auto port = ParseSerialPortSpec(*arguments.dut);
    if (!port) return rig::MakeError("--dut " + port.error().message);
    choice.port = std::move(port).value();
    if (arguments.can) {
      if (auto uri = ParseDutCanBusUri(*arguments.can); !uri) {
        return rig::MakeError("--can: " + uri.error().message);
      }
      choice.port.can_uri = *arguments.can;
    }
  }
  return {};
}

// "exec:PROGRAM[,ARG...]" into the program and its arguments.
rig::Result<void> ParseProgram(const std::string& word, ProcessDutOptions& options) {
  std::vector<std::string> parts;
  std::size_t start = word.find(':') + 1;
  while (true) {
    const std::size_t comma = word.find(',', start);
    parts.push_back(word.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (parts.front().empty()) {
    return rig::MakeError("--dut \"" + word + "\": exec: needs a program (exec:PROGRAM[,ARG...])");
  }
  options.program = parts.front();
  options.program_args.assign(parts.begin() + 1, parts.end());
  return {};
}

// "listen:ADDRESS:PORT[,token=FILE]" into where to wait and the token's file.
rig::Result<void> ParseListen(const std::string& word, ProcessDutOptions& options) {
  const auto bad = [&word](const std::string& why) {
    return rig::MakeError("--dut \"" + word + "\": " + why + " (listen:ADDRESS:PORT[,token=FILE])");
  };
  const std::string rest = word.substr(word.find(':') + 1);
  const std::size_t comma = rest.find(',');
  const std::string endpoint = rest.substr(0, comma);
  const std::size_t colon = endpoint.rfind(':');
  if (colon == std::string::npos || colon == 0) return bad("needs an address and a port");
  const std::string port = endpoint.substr(colon + 1);
  const auto number = rig::ParseNumber<std::uint16_t>(port, "port");
  if (!number || number.value() < 1 || number.value() > 65534) {
    return bad("port \"" + port + "\" is not a whole number from 1 to 65534");
  }
  options.token_file = "hilrig_link_token";
  if (comma != std::string::npos) {
    const std::string option = rest.substr(comma + 1);
    if (!option.starts_with("token=") || option.size() == 6)
      return bad("unknown \"" + option + "\"");
    options.token_file = option.substr(6);
  }
  options.listen = true;
  options.transport = DutLinkTransport::kTcp;
  options.listen_address = endpoint.substr(0, colon);
  options.listen_port = number.value();
  options.start_timeout_s = kListenStartTimeoutS;
  return {};
}

rig::Result<void> ParseProcessOptions(const DutArguments& arguments, DutChoice& choice) {
  ProcessDutOptions& options = choice.process;
  if (choice.kind == DutKind::kExec) {
    if (auto program = ParseProgram(*arguments.dut, options); !program) return program.error();
  }
  if (choice.kind == DutKind::kListen) {
    if (auto listen = ParseListen(*arguments.dut, options); !listen) return listen.error();
  }
  if (arguments.link && *arguments.link == "tcp") options.transport = DutLinkTransport::kTcp;
  if (arguments.can) {
    if (auto uri = ParseDutCanBusUri(*arguments.can); !uri) {
      return rig::MakeError("--can: " + uri.error().message);
    }
    options.can_uri = *arguments.can;
  }
  auto seconds = ParseTimeout(arguments.timeout_s, options.answer_timeout_s);
  if (!seconds) return seconds.error();
  options.answer_timeout_s = seconds.value();
  if (auto valid = ValidateProcessDutOptions(options); !valid) {
    return rig::MakeError("--dut-timeout-s: " + valid.error().message);
  }
  return {};
}

// exec: or listen: on the line link: the serial DUT's options, the lines the DUT dials.
rig::Result<void> ParseLineOptions(const DutArguments& arguments, DutChoice& choice) {
  choice.line = true;
  const ProcessDutOptions& process = choice.process;
  DialedLineSpec& dialed = choice.dialed;
  if (choice.kind == DutKind::kExec) {
    dialed.program = process.program;
    dialed.program_args = process.program_args;
  } else {
    dialed.address = process.listen_address;
    dialed.port = process.listen_port;
    dialed.token_file = process.token_file;
    choice.serial.start_timeout_s = kListenStartTimeoutS;
  }
  return ParseSerialOptions(arguments, choice);
}

// "px4-hitl:DEVICE[,baud=N]": the board's serial device and its baud rate.
rig::Result<void> ParseBoardPort(const std::string& word, MavlinkDutOptions& link) {
  auto port = ParseSerialDevice(word.substr(std::string("px4-hitl:").size()), link.baud);
  if (!port) {
    return rig::MakeError("--dut \"" + word + "\": " + port.error().message +
                          " (px4-hitl:DEVICE[,baud=N])");
  }
  link.start_stand_in = false;
  link.start_timeout_s = kListenStartTimeoutS;
  link.serial_device = port.value().device;
  link.baud = port.value().baud;
  return {};
}

// mavlink-emu, px4-sitl[:PORT]: the watchdog, lockstep only (MakeDutFactory refuses real time);
// PX4 is waited for on its own ports, and a person starts it. mavlink-emu-hitl,
// px4-hitl:DEVICE[,baud=N]: a board on a serial line, real time only.
rig::Result<void> ParseMavlinkOptions(const DutArguments& arguments, DutChoice& choice) {
  MavlinkDutOptions& link = choice.mavlink.link;
  if (choice.kind == DutKind::kPx4Sitl) {
    link.start_stand_in = false;
    link.first_answers_late = true;
    link.sim_port = kPx4SimulatorPort;
    link.api_port = kPx4ApiPort;
    link.start_timeout_s = kListenStartTimeoutS;
    const std::string& word = *arguments.dut;
    if (word.size() > 8) {
      const std::string port = word.substr(9);
      const auto number = rig::ParseNumber<std::uint16_t>(port, "port");
      if (!number || number.value() < 1) {
        return rig::MakeError("--dut \"" + word + "\": port \"" + port +
                              "\" is not a whole number from 1 to 65535 (px4-sitl[:PORT])");
      }
      link.sim_port = number.value();
    }
  }
  if (OnABoard(choice.kind)) {
    link.hitl = true;
    if (choice.kind == DutKind::kPx4Hitl) {
      if (auto board = ParseBoardPort(*arguments.dut, link); !board) return board;
    }
  }
  LinkedDutOptions& session = choice.mavlink.session;
  auto seconds = ParseTimeout(arguments.timeout_s, session.answer_timeout_s);
  if (!seconds) return seconds.error();
  session.answer_timeout_s = seconds.value();
  if (auto valid = ValidateMavlinkDutOptions(link); !valid) {
    return rig::MakeError("--dut " + *arguments.dut + ": " + valid.error().message);
  }
  // The pacing is the run's: MakeDutFactory refuses the one the kind cannot take.
  if (auto valid = ValidateLinkedDutOptions(session); !valid) {
    return rig::MakeError("--dut-timeout-s: " + valid.error().message);
  }
  return {};
}

DutFactory MavlinkFactory(MavlinkDutPortOptions options, const DutFactorySeams& seams) {
  options.link.stop_requested = seams.stop_requested;
  options.link.notes = seams.notes;
  // A board runs in real time on a wall clock of the DUT's own, as a serial DUT does.
  std::shared_ptr<const rig::SteadyClock> dut_clock;
  if (options.link.hitl) {
    dut_clock = std::make_shared<const rig::SteadyClock>();
    options.session.clock = dut_clock.get();
    options.session.pacing = DutPacing::kRealtime;
  }
  return [options, dut_clock](const ScenarioConfig& config, std::unique_ptr<rig::CanBus> bus,
                              double control_period_s) -> rig::Result<std::unique_ptr<DutPort>> {
    return std::unique_ptr<DutPort>(std::make_unique<MavlinkDut>(
        FirmwareFor(config), std::move(bus), control_period_s, options));
  };
}

DutFactory SinglePrecisionFactory() {
  return [](const ScenarioConfig& config, std::unique_ptr<rig::CanBus> bus,
            double control_period_s) -> rig::Result<std::unique_ptr<DutPort>> {
    return std::unique_ptr<DutPort>(std::make_unique<SinglePrecisionInProcessDut>(
        FirmwareFor<float>(config), std::move(bus), control_period_s));
  };
}

// In real time the process DUT reads a wall clock of its own for its watchdog and latencies
// (differences only, so its epoch does not matter); the factory keeps it alive for every DUT it
// starts.
DutFactory ProcessFactory(ProcessDutOptions options, bool realtime, const DutFactorySeams& seams) {
  options.stop_requested = seams.stop_requested;
  options.notes = seams.notes;
  std::shared_ptr<const rig::SteadyClock> dut_clock;
  if (realtime) {
    dut_clock = std::make_shared<const rig::SteadyClock>();
    options.wall_clock = dut_clock.get();
    options.pacing = DutPacing::kRealtime;
  }
  return [options, dut_clock](const ScenarioConfig& config, std::unique_ptr<rig::CanBus> bus,
                              double control_period_s) -> rig::Result<std::unique_ptr<DutPort>> {
    return std::unique_ptr<DutPort>(std::make_unique<ProcessDut>(
        FirmwareFor(config), std::move(bus), control_period_s, options));
  };
}

// In real time a serial DUT reads a wall clock of its own, as a process DUT does.
DutFactory SerialFactory(SerialLineOpener opener, SerialDutOptions options, bool realtime) {
  std::shared_ptr<const rig::SteadyClock> dut_clock;
  if (realtime) {
    dut_clock = std::make_shared<const rig::SteadyClock>();
    options.clock = dut_clock.get();
    options.pacing = DutPacing::kRealtime;
  }
  return [opener, options, dut_clock](
             const ScenarioConfig& config, std::unique_ptr<rig::CanBus> bus,
             double control_period_s) -> rig::Result<std::unique_ptr<DutPort>> {
    return std::unique_ptr<DutPort>(std::make_unique<SerialDut>(FirmwareFor(config), std::move(bus),
                                                                control_period_s, opener, options));
  };
}

}  // namespace

const char* DutKindName(DutKind kind) {
  switch (kind) {
    case DutKind::kInProcess:
      return "inproc";
    case DutKind::kInProcessFloat:
      return "inproc-float";
    case DutKind::kProcess:
      return "process";
    case DutKind::kExec:
      return "exec";
    case DutKind::kListen:
      return "listen";
    case DutKind::kQemu:
      return "qemu";
    case DutKind::kSerial:
      return "serial";
    case DutKind::kMavlinkEmu:
      return "mavlink-emu";
    case DutKind::kPx4Sitl:
      return "px4-sitl";
    case DutKind::kMavlinkEmuHitl:
      return "mavlink-emu-hitl";
    case DutKind::kPx4Hitl:
      return "px4-hitl";
  }
  return "unknown";
}

rig::Result<DutChoice> ParseDutChoice(const DutArguments& arguments) {
  auto kind = ParseKind(arguments.dut);
  if (!kind) return kind.error();
  DutChoice choice;
  choice.kind = kind.value();
  if (auto fit = CheckOptionsFit(choice.kind, arguments); !fit) return fit.error();
  if (choice.kind == DutKind::kQemu || choice.kind == DutKind::kSerial) {
    if (auto parsed = ParseSerialOptions(arguments, choice); !parsed) return parsed.error();
  }
  if (AProcess(choice.kind)) {
    if (auto parsed = ParseProcessOptions(arguments, choice); !parsed) return parsed.error();
  }
  if (OverMavlink(choice.kind)) {
    if (auto parsed = ParseMavlinkOptions(arguments, choice); !parsed) return parsed.error();
  }
  if (arguments.link && *arguments.link == "line") {
    if (auto parsed = ParseLineOptions(arguments, choice); !parsed) return parsed.error();
  }
  return choice;
}

rig::Result<DutFactory> MakeDutFactory(const DutChoice& choice, bool realtime,
                                       const DutFactorySeams& seams) {
  switch (choice.kind) {
    case DutKind::kInProcess:
      return DutFactory();
    case DutKind::kInProcessFloat:
      return SinglePrecisionFactory();
    case DutKind::kExec:
    case DutKind::kListen:
      if (choice.line) {
        DialedLineSpec dialed = choice.dialed;
        dialed.stop_requested = seams.stop_requested;
        dialed.notes = seams.notes;
        return SerialFactory(DialedLines(dialed), choice.serial, realtime);
      }
      return ProcessFactory(choice.process, realtime, seams);
    case DutKind::kProcess:
      return ProcessFactory(choice.process, realtime, seams);
    case DutKind::kQemu: {
      auto image = FindTargetImage(choice.target_image);
      if (!image) return rig::MakeError("--dut qemu: " + image.error().message);
      SerialDutOptions options = choice.serial;
      options.emulated_core = true;
      return SerialFactory(QemuLines({image.value(), ""}), options, realtime);
    }
    case DutKind::kSerial:
      return SerialFactory(SerialPortLines(choice.port), choice.serial, realtime);
    case DutKind::kMavlinkEmuHitl:
    case DutKind::kPx4Hitl:
      if (!realtime) {
        return rig::MakeError(std::string("--dut ") + DutKindName(choice.kind) +
                              " runs in real time only: a board keeps its own clock (add "
                              "--realtime)");
      }
      return MavlinkFactory(choice.mavlink, seams);
    case DutKind::kMavlinkEmu:
    case DutKind::kPx4Sitl:
      if (realtime) {
        return rig::MakeError(std::string("--dut ") + DutKindName(choice.kind) +
                              " runs in lockstep only: PX4's simulator contract gives the DUT no "
                              "clock but the sensor steps (leave out --realtime)");
      }
      return MavlinkFactory(choice.mavlink, seams);
  }
  return rig::MakeError("unknown DUT kind");
}

}  // namespace hilrig::host
