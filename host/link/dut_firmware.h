// The firmware a DUT is flashed with, as the HIL link carries it: the flight controller's, the
// tactile front end's and the grasp admittance's parameters. The link owns this type so that it
// depends on the firmware alone; which numbers a scene gives it (FirmwareFor in
// host/dut/firmware_config.h) is the harness's business.
#pragma once

#include <optional>

#include "dut_fw/flight_controller.h"
#include "dut_fw/grasp_controller.h"
#include "dut_fw/tactile_processor.h"

namespace hilrig::host {

// Built for the firmware's scalar: double as on the host, or float as on the target.
template <typename S>
struct BasicDutFirmware {
  dut_fw::FlightControllerParams<S> flight;
  std::optional<dut_fw::TactileProcessorParams<S>> tactile;
  dut_fw::GraspAdmittanceParams<S> grasp;
  // false: the ablation that keeps the tactile force out of the admittance and the thrust.
  bool external_force_in_position_loop = true;
};
using DutFirmware = BasicDutFirmware<double>;

}  // namespace hilrig::host
