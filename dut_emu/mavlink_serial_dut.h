// dut_emu --mavlink-serial: PX4's stand-in as a board in HITL, both MAVLink links on one serial
// line (a board's USB port, or the pseudo-terminal the rig's `--dut mavlink-emu-hitl` opens). It
// announces itself with a HEARTBEAT once a second until the first HIL_SENSOR, then answers each
// HIL_SENSOR at once, as MavlinkDut does on sockets; the rig paces it in real time. The stand-in
// still steps its controller on HIL_SENSOR's time_usec, which a real board would ignore for its
// own clock.
#pragma once

#include <atomic>
#include <ostream>

#include "dut_emu/mavlink_dut.h"

namespace hilrig::dut_emu {

// Runs `dut` on the serial line options.serial_device until the rig closes it, a message ends the
// DUT, the line fails or `stop_requested` (may be null) is set; says why in one line on `log` and
// returns dut_emu's exit code, as RunMavlinkDut does. Allocates on start only.
int RunMavlinkSerialDut(const MavlinkDutOptions& options, const std::atomic<bool>* stop_requested,
                        std::ostream& log, MavlinkDut& dut);

}  // namespace hilrig::dut_emu
