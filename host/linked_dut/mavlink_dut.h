// A flight stack over MAVLink as the DUT (`hilrig run --dut mavlink-emu`): the linked-DUT session
// (host/linked_dut/linked_dut.h) over the MAVLink link (host/linked_dut/mavlink_dut_link.h), with
// PX4's stand-in `dut_emu --mavlink` behind it. Lockstep only: the stand-in keeps PX4's SITL
// contract, in which the sensor steps are the DUT's only clock.
#pragma once

#include <memory>

#include "host/link/dut_firmware.h"
#include "host/linked_dut/linked_dut.h"
#include "host/linked_dut/mavlink_dut_link.h"
#include "rig/can_bus.h"

namespace hilrig::host {

struct MavlinkDutPortOptions {
  MavlinkDutOptions link;
  LinkedDutOptions session;  // its pacing must be lockstep
};

// Checks both parts; the wrong pacing is refused by name (lockstep for a board, real time for
// the simulator link).
rig::Result<void> ValidateMavlinkDutPortOptions(const MavlinkDutPortOptions& options);

class MavlinkDut final : public LinkedDut {
 public:
  // `runner_bus` is the DUT's endpoint on the runner's bus: the frames that reach it go to the DUT
  // as CAN_FRAME. Nothing starts until Start.
  MavlinkDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> runner_bus,
             double control_period_s, const MavlinkDutPortOptions& options);

  // Refuses the wrong pacing by name, then starts as every linked DUT does.
  rig::Result<void> Start() override;
  // A flight stack fuses them: HIL_SENSOR carries the magnetometer and barometer, HIL_GPS the fix.
  bool TakesNavigationSensors() const override { return true; }

 private:
  MavlinkDutPortOptions options_;
};

}  // namespace hilrig::host
