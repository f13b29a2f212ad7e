// The firmware a DUT process is flashed with, as it crosses the HIL link: DutFirmware (what
// FirmwareFor() makes of a scenario) and the control period, to and from the DutConfig message.
// Every number is carried as it is, so that the DUT process and the in-process DUT are configured
// bit for bit alike; the decoding side checks the shape (six tactile nodes, valid chip setting, a
// positive finite control period) and every number (host/link/firmware_check.h), and refuses
// anything else with an error that names the field.
#pragma once

#include "host/link/dut_firmware.h"
#include "proto/hil_link.pb.h"
#include "rig/result.h"

namespace hilrig::host {

struct DutSetup {
  DutFirmware firmware;
  double control_period_s = 0;
};

proto::DutConfig ToDutConfig(const DutFirmware& firmware, double control_period_s);
rig::Result<DutSetup> FromDutConfig(const proto::DutConfig& config);

}  // namespace hilrig::host
