#include "host/dut/firmware_config.h"

namespace hilrig::host {

dut_fw::FlightControllerParams<double> FirmwareParamsFor(const QuadrotorParams& vehicle) {
  auto params = dut_fw::DefaultFlightControllerParams<double>(vehicle.body.mass_kg);
  params.position.gravity_m_s2 = vehicle.gravity_m_s2;
  params.estimator.gravity_m_s2 = vehicle.gravity_m_s2;
  params.mixer.arm_length_m = vehicle.rotors.arm_length_m;
  params.mixer.torque_per_thrust_m = vehicle.rotors.torque_per_thrust_m;
  params.mixer.max_thrust_per_rotor_n = vehicle.rotors.max_thrust_n;
  params.position.max_collective_thrust_n =
      std::min(params.position.max_collective_thrust_n, 4 * vehicle.rotors.max_thrust_n);
  return params;
}

}  // namespace hilrig::host
