// The firmware a DUT is flashed with, as the HIL link carries it: the flight controller's, the
// tactile front end's and the grasp admittance's parameters. The link owns this type so that it
// depends on the firmware alone; which numbers a scene gives it (FirmwareFor in
// host/dut/firmware_config.h) is the harness's business.
#pragma once

#include "dut_fw/dut_core.h"

namespace hilrig::host {

// Built for the firmware's scalar: double as on the host, or float as on the target. The
// parameters are the ones DutCore takes, so the link carries what every DUT is built from.
template <typename S>
using BasicDutFirmware = dut_fw::DutCoreParams<S>;
using DutFirmware = BasicDutFirmware<double>;

}  // namespace hilrig::host
