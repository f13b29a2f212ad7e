// The firmware configuration the DUT is flashed with for a given vehicle: the controller's default
// tuning with the vehicle's mass, rotor geometry and gravity filled in. On a real vehicle these
// numbers come from the airframe's parameter file; in the rig they come from the scenario.
#pragma once

#include "dut_fw/flight_controller.h"
#include "host/plant/quadrotor.h"

namespace hilrig::host {

dut_fw::FlightControllerParams<double> FirmwareParamsFor(const QuadrotorParams& vehicle);

}  // namespace hilrig::host
