// The firmware configuration the DUT is flashed with for a given scene: the controller's default
// tuning with the vehicle's mass, rotor geometry and gravity filled in, and the tactile front end's
// layout and calibration. On a real vehicle these numbers come from the airframe's parameter file
// and the lab's calibration file; in the rig they come from the scenario.
#pragma once

#include <optional>

#include "dut_fw/flight_controller.h"
#include "dut_fw/grasp_controller.h"
#include "dut_fw/tactile_processor.h"
#include "host/link/dut_firmware.h"
#include "host/plant/quadrotor.h"
#include "host/scenario/scenario_config.h"

namespace hilrig::host {

// Each is built for the firmware's scalar: double as on the host, or float as on the target
// (explicitly instantiated for both).
template <typename S = double>
dut_fw::FlightControllerParams<S> FirmwareParamsFor(const QuadrotorParams& vehicle);

// Empty when the scene has no tactile nodes. Needs config.hall_sensors.calibration loaded.
template <typename S = double>
std::optional<dut_fw::TactileProcessorParams<S>> FirmwareTactileParamsFor(
    const ScenarioConfig& config);

// The grasp admittance with the scene's gains and ablation switch; the servo's range is the
// gripper's.
template <typename S = double>
dut_fw::GraspAdmittanceParams<S> FirmwareGraspParamsFor(const ScenarioConfig& config);

// Everything the DUT is flashed with.
template <typename S = double>
BasicDutFirmware<S> FirmwareFor(const ScenarioConfig& config);

}  // namespace hilrig::host
