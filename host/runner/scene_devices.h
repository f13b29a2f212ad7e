// The emulated devices of a scene, built in the order they tick within a physics tick: the IMU,
// the VIO, then the Hall sensor nodes. A new emulated device is added to a run here.
#pragma once

#include <memory>
#include <vector>

#include "host/runner/device_emulator.h"
#include "host/scenario/scenario_config.h"
#include "rig/emulated_bus.h"

namespace hilrig::host {

// `config` must outlive the devices; CAN-side devices connect to `bus` here, in this order.
std::vector<std::unique_ptr<DeviceEmulator>> MakeSceneDevices(const ScenarioConfig& config,
                                                              rig::EmulatedBus& bus);

}  // namespace hilrig::host
