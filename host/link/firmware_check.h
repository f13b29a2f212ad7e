// The check of a firmware configuration that arrives over the HIL link, before a DUT is built from
// it: a peer's numbers must not reach the controller unchecked (a NaN gain runs as silently as a
// good one). Every number must be finite; masses, rates, periods and limits must be positive, gains
// and dampings not negative, fractions within [0, 1], ranges ordered, and counts and node ids
// within what the firmware's arrays hold. The first problem is refused with the field's name, e.g.
// "flight.position.mass_kg is nan: must be finite and > 0". Every firmware FirmwareFor() makes of a
// scenario the rig accepts passes.
#pragma once

#include "host/link/dut_firmware.h"
#include "rig/result.h"

namespace hilrig::host {

rig::Result<void> CheckDutFirmware(const DutFirmware& firmware);

}  // namespace hilrig::host
