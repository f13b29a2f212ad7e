// dut_emu --serial: the DUT's side of the serial HIL link (dut_link/serial_session.h with
// dut_fw/dut_core_controller.h, the very code the STM32 image runs, here with the host's float
// build) on a tty or a pseudo-terminal in raw mode, so the runner's serial path can be driven
// without a board. The link line carries the framed LinkMessages; the optional bridge line the
// sensor nodes' UART frames. The work per step is not measured here (work_cycles 0). It runs until
// a signal asks it to stop or the line goes away; a runner's Bye only ends one run, as on a board.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "dut_fw/serial_line_rates.h"
#include "rig/result.h"

namespace hilrig::dut_emu {

struct SerialDutOptions {
  std::string link_path;
  std::optional<std::string> bridge_path;
  std::uint32_t baud = dut_fw::kLinkBaud;
  std::uint32_t bridge_baud = dut_fw::kBridgeBaud;
};

extern const char* const kSerialDutUsage;

// "PATH[,baud=N][,bridge=PATH2][,bridge_baud=N]", as --serial takes it; an unknown key or a baud
// rate termios has no constant for is an error that says so.
rig::Result<SerialDutOptions> ParseSerialSpec(const std::string& spec);

// Returns dut_emu's exit code (dut_emu_server.h) and says why on `log`: kExitOk on a stop
// request or when the line closes between runs, kExitFailed when it closes mid-run or fails.
int RunSerialDut(const SerialDutOptions& options, const std::atomic<bool>* stop_requested,
                 std::ostream& log);

}  // namespace hilrig::dut_emu
