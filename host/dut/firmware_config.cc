#include "host/dut/firmware_config.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "rig/check.h"

namespace hilrig::host {

template <typename S>
dut_fw::FlightControllerParams<S> FirmwareParamsFor(const QuadrotorParams& vehicle) {
  auto params = dut_fw::DefaultFlightControllerParams<S>(S(vehicle.body.mass_kg));
  params.position.gravity_m_s2 = S(vehicle.gravity_m_s2);
  params.estimator.gravity_m_s2 = S(vehicle.gravity_m_s2);
  params.mixer.arm_length_m = S(vehicle.rotors.arm_length_m);
  params.mixer.torque_per_thrust_m = S(vehicle.rotors.torque_per_thrust_m);
  params.mixer.max_thrust_per_rotor_n = S(vehicle.rotors.max_thrust_n);
  params.position.max_collective_thrust_n =
      std::min(params.position.max_collective_thrust_n, S(4 * vehicle.rotors.max_thrust_n));
  return params;
}

template <typename S>
std::optional<dut_fw::TactileProcessorParams<S>> FirmwareTactileParamsFor(
    const ScenarioConfig& config) {
  const HallSensorConfig& hall = config.hall_sensors;
  if (!hall.tactile_enabled) return std::nullopt;
  HILRIG_CHECK(hall.calibration.has_value(), "LoadTactileCalibration must run before the DUT");
  const proto::Calibration& calibration = *hall.calibration;
  dut_fw::TactileProcessorParams<S> params;
  params.film = {S(calibration.film().k1()), S(calibration.film().c1()), S(calibration.film().k2()),
                 S(calibration.film().c2())};
  params.chip_setting = hall.tactile[0].chip.setting;
  // Clamped before the cast: validation bounds zeroing_s, and a cast of an out-of-range double
  // would be undefined rather than an error.
  params.zeroing_samples =
      static_cast<std::uint32_t>(std::clamp(std::round(hall.zeroing_s * hall.node_rate_hz), 1.0,
                                            double(std::numeric_limits<std::uint32_t>::max())));
  params.compensation_enabled = hall.compensation;
  params.force_average_samples = hall.force_average_samples;
  for (int i = 0; i < kTactileSensorCount; ++i) {
    const TactileSensorParams& sensor = hall.tactile[i];
    const Eigen::Matrix3d body_from_sensor = sensor.mounting_body_from_sensor.toRotationMatrix();
    auto& node = params.nodes[i];
    node.node_id = sensor.node_id;
    node.rotation_sensor_from_reference =
        RotationSensorFromReference(sensor, hall.reference).cast<S>();
    node.rotation_body_from_sensor = body_from_sensor.cast<S>();
    node.contact_normal_sensor =
        (body_from_sensor.transpose() * ContactNormalBody(sensor)).cast<S>();
    const proto::Vector3& a = calibration.sensors(i).a();
    node.gain_a = Eigen::Vector3d(a.x(), a.y(), a.z()).cast<S>();
  }
  return params;
}

template <typename S>
dut_fw::GraspAdmittanceParams<S> FirmwareGraspParamsFor(const ScenarioConfig& config) {
  const GripperConfig& gripper = config.gripper;
  dut_fw::GraspAdmittanceParams<S> params;
  params.mass = S(gripper.controller_mass.value_or(params.mass));
  params.damping = S(gripper.controller_damping.value_or(params.damping));
  params.stiffness = S(gripper.controller_stiffness.value_or(params.stiffness));
  params.open_angle_rad = S(gripper.servo.min_angle_rad);
  params.closed_angle_rad = S(gripper.servo.max_angle_rad);
  params.force_feedback = gripper.force_feedback;
  // The firmware knows its own servo: how long a move to the reference angle takes before force
  // feedback may start integrating.
  params.servo_max_rate_rad_s = S(gripper.servo.max_rate_rad_s);
  params.servo_settle_s = S(3 * gripper.servo.time_constant_s);
  return params;
}

template <typename S>
BasicDutFirmware<S> FirmwareFor(const ScenarioConfig& config) {
  return {FirmwareParamsFor<S>(config.vehicle), FirmwareTactileParamsFor<S>(config),
          FirmwareGraspParamsFor<S>(config), config.gripper.external_force_in_position_loop};
}

template dut_fw::FlightControllerParams<double> FirmwareParamsFor(const QuadrotorParams&);
template dut_fw::FlightControllerParams<float> FirmwareParamsFor(const QuadrotorParams&);
template std::optional<dut_fw::TactileProcessorParams<double>> FirmwareTactileParamsFor(
    const ScenarioConfig&);
template std::optional<dut_fw::TactileProcessorParams<float>> FirmwareTactileParamsFor(
    const ScenarioConfig&);
template dut_fw::GraspAdmittanceParams<double> FirmwareGraspParamsFor(const ScenarioConfig&);
template dut_fw::GraspAdmittanceParams<float> FirmwareGraspParamsFor(const ScenarioConfig&);
template BasicDutFirmware<double> FirmwareFor(const ScenarioConfig&);
template BasicDutFirmware<float> FirmwareFor(const ScenarioConfig&);

}  // namespace hilrig::host
