// dut_emu: the dut_fw controller as its own process on the HIL link (see dut_emu_server.h).
#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "dut_emu/dut_emu_server.h"
#include "dut_emu/mavlink_dut.h"
#include "dut_emu/serial_dut.h"
#include "dut_link/posix/line_io.h"
#include "rig/printable_text.h"

int main(int argc, char** argv) {
  // What dut_emu prints may quote its peer (a runner's bye reason, a device name): no control
  // character reaches the terminal.
  hilrig::rig::PrintableStreamBuf printable_stderr(std::cerr.rdbuf());
  std::cerr.rdbuf(&printable_stderr);
  struct RestoreStderr {
    std::streambuf* original;
    ~RestoreStderr() { std::cerr.rdbuf(original); }
  } restore{printable_stderr.target()};
  const std::vector<std::string> args(argv, argv + argc);
  if (args.size() == 2 && (args[1] == "--help" || args[1] == "-h")) {
    std::cout << hilrig::dut_emu::kDutEmuUsage << hilrig::dut_emu::kSerialDutUsage
              << hilrig::dut_emu::kMavlinkDutUsage;
    return hilrig::dut_emu::kExitOk;
  }
  // On a serial line the tty itself is the DUT's authority: no link token.
  if (args.size() >= 2 && args[1] == "--serial") {
    auto serial = args.size() == 3 ? hilrig::dut_emu::ParseSerialSpec(args[2])
                                   : hilrig::rig::Result<hilrig::dut_emu::SerialDutOptions>(
                                         hilrig::rig::MakeError("--serial takes one argument"));
    if (!serial) {
      std::cerr << "dut_emu: " << serial.error().message << "\n"
                << hilrig::dut_emu::kSerialDutUsage;
      return hilrig::dut_emu::kExitUsage;
    }
    return hilrig::dut_emu::RunSerialDut(serial.value(), hilrig::dut_link::StopOnSignals(),
                                         std::cerr);
  }
  // PX4 SITL's part on the MAVLink simulator link, its options in any order. MAVLink has no link
  // token: like PX4, the stand-in proves nothing to the rig.
  if (std::find(args.begin() + 1, args.end(), "--mavlink") != args.end() ||
      std::find(args.begin() + 1, args.end(), "--mavlink-serial") != args.end()) {
    auto mavlink = hilrig::dut_emu::ParseMavlinkArgs(args);
    if (!mavlink) {
      std::cerr << "dut_emu: " << mavlink.error().message << "\n"
                << hilrig::dut_emu::kMavlinkDutUsage;
      return hilrig::dut_emu::kExitUsage;
    }
    return hilrig::dut_emu::RunMavlinkDut(mavlink.value(), hilrig::dut_link::StopOnSignals(),
                                          std::cerr);
  }
  auto options = hilrig::dut_emu::ParseDutEmuArgs(args);
  if (!options) {
    std::cerr << "dut_emu: " << options.error().message << "\n" << hilrig::dut_emu::kDutEmuUsage;
    return hilrig::dut_emu::kExitUsage;
  }
  // The inherited shared-memory link reaches nobody but this process: no token to prove.
  if (options.value().link_shm_fd < 0) {
    auto token = hilrig::dut_emu::LoadLinkToken(options.value(),
                                                std::getenv(hilrig::host::kLinkTokenEnvironment));
    if (!token) {
      std::cerr << "dut_emu: " << token.error().message << "\n";
      return hilrig::dut_emu::kExitUsage;
    }
    options.value().link_token = token.value();
  }
  // Nothing this process starts needs the secret.
  ::unsetenv(hilrig::host::kLinkTokenEnvironment);
  // Writes to a vanished runner must be errors, not a silent death; sends use MSG_NOSIGNAL too.
  return hilrig::dut_emu::RunDutEmu(options.value(), hilrig::dut_link::StopOnSignals(), std::cerr);
}
