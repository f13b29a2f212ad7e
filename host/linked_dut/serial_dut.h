// A DUT on serial lines: a board's UART or USB CDC port, an emulated MCU's USARTs, or a program
// that dials the rig's line link (host/linked_dut/dialed_lines.h). The HIL link runs on one byte
// stream in the framing of host/link/line_link.h; the tactile CAN frames that reach the runner's
// "dut" endpoint travel as a sensor node's UART bridge frames on a second stream, the way a node's
// UART carries the bus to the flight controller on the vehicle (or onto the board's own CAN port).
// The session (lockstep or real time, the watchdog, the first failure that sticks, the emulator's
// end) is LinkedDut's; the line's half (the handshake, the compact per-tick messages, the retry of
// a lost step) is host/linked_dut/serial_dut_link.h.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "host/dut/dut_port.h"
#include "host/link/byte_stream.h"
#include "host/link/child_process.h"
#include "host/link/dut_firmware.h"
#include "host/link/link_token.h"
#include "host/linked_dut/linked_dut.h"
#include "rig/can_bus.h"
#include "rig/clock.h"

namespace hilrig::host {

// What a serial DUT runs on.
struct SerialLines {
  std::unique_ptr<ByteStream> link;
  // The sensor nodes' UART bridge; null when none is wired (tactile frames are then counted and
  // dropped, unless `can` carries them).
  std::unique_ptr<ByteStream> bridge;
  // A CAN bus the DUT reads its sensors on itself (a board's own CAN port on a bench): the frames
  // go there instead of the bridge line, unannounced, and reach the DUT when the bus delivers
  // them, so such a run's sensor timing follows the wall clock. Null: the bridge line.
  std::unique_ptr<rig::CanBus> can;
  std::string can_uri;                   // what `can` is, for the description
  std::optional<ChildProcess> emulator;  // the process behind the lines, when there is one
  std::string description;               // "a board on /dev/ttyACM0 at 2000000 baud"
  // How long one byte takes to reach the DUT (10 bits at the baud rate; an emulator's USART is
  // slower). The retries wait twice the time the bytes they repeat need, on top of their timeout,
  // so a slow line is not taken for a lost frame.
  double byte_time_s = 0;
  // A line anyone on the host could reach (a TCP port): the DUT's hello must carry this token.
  std::optional<LinkToken> link_token;
};

// Opens the lines within `timeout_s` (an emulator takes a moment to open its ports).
using SerialLineOpener = std::function<rig::Result<SerialLines>(double timeout_s)>;

struct SerialDutOptions {
  double answer_timeout_s = 1.0;  // the watchdog: how long a step may go unanswered
  double start_timeout_s = 10.0;  // for the DUT to answer the hello and take the configuration
  double hello_interval_s = 0.1;
  double config_retry_s = 0.5;
  // Lockstep: the same SerialStep again when no answer came within this (a frame was lost).
  double step_retry_s = 0.05;
  // The watchdog's and the handshake's clock (it must outlive the DUT); null: a SteadyClock of
  // the DUT's own, for lockstep only.
  const rig::Clock* clock = nullptr;
  // Lockstep, or real time (which needs `clock`).
  DutPacing pacing = DutPacing::kLockstep;
  // The board is QEMU under -icount: its work counts are its virtual time, not core cycles.
  bool emulated_core = false;
};

// Checks the options: positive finite timeouts, a retry shorter than the watchdog.
rig::Result<void> ValidateSerialDutOptions(const SerialDutOptions& options);

// The serial line's session options: its pacing, watchdog and clock.
LinkedDutOptions SessionOptionsOf(const SerialDutOptions& options);

// A DUT on serial lines: the linked-DUT session (host/linked_dut/linked_dut.h) over the serial line
// (host/linked_dut/serial_dut_link.h).
class SerialDut final : public LinkedDut {
 public:
  // `runner_bus` is the DUT's endpoint on the runner's emulated bus. Nothing opens until Start.
  SerialDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> runner_bus,
            double control_period_s, SerialLineOpener open_lines, const SerialDutOptions& options);
};

}  // namespace hilrig::host
