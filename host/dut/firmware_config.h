// The firmware configuration the DUT is flashed with for a given scene: the controller's default
// tuning with the vehicle's mass, rotor geometry and gravity filled in, and the tactile front end's
// layout and calibration. On a real vehicle these numbers come from the airframe's parameter file
// and the lab's calibration file; in the rig they come from the scenario.
#pragma once

#include <optional>

#include "dut_fw/flight_controller.h"
#include "dut_fw/tactile_processor.h"
#include "host/plant/quadrotor.h"
#include "host/scenario/scenario_config.h"

namespace hilrig::host {

dut_fw::FlightControllerParams<double> FirmwareParamsFor(const QuadrotorParams& vehicle);

// Empty when the scene has no tactile nodes. Needs config.hall_sensors.calibration loaded.
std::optional<dut_fw::TactileProcessorParams<double>> FirmwareTactileParamsFor(
    const ScenarioConfig& config);

}  // namespace hilrig::host
