#include "host/dut/firmware_config.h"

#include <cmath>

#include "rig/check.h"

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

std::optional<dut_fw::TactileProcessorParams<double>> FirmwareTactileParamsFor(
    const ScenarioConfig& config) {
  const HallSensorConfig& hall = config.hall_sensors;
  if (!hall.tactile_enabled) return std::nullopt;
  HILRIG_CHECK(hall.calibration.has_value(), "LoadTactileCalibration must run before the DUT");
  const proto::Calibration& calibration = *hall.calibration;
  dut_fw::TactileProcessorParams<double> params;
  params.film = {calibration.film().k1(), calibration.film().c1(), calibration.film().k2(),
                 calibration.film().c2()};
  params.chip_setting = hall.tactile[0].chip.setting;
  params.zeroing_samples =
      static_cast<std::uint32_t>(std::max(1L, std::lround(hall.zeroing_s * hall.node_rate_hz)));
  params.compensation_enabled = hall.compensation;
  for (int i = 0; i < kTactileSensorCount; ++i) {
    const TactileSensorParams& sensor = hall.tactile[i];
    const Eigen::Matrix3d body_from_sensor = sensor.mounting_body_from_sensor.toRotationMatrix();
    auto& node = params.nodes[i];
    node.node_id = sensor.node_id;
    node.rotation_sensor_from_reference = RotationSensorFromReference(sensor, hall.reference);
    node.rotation_body_from_sensor = body_from_sensor;
    node.contact_normal_sensor = body_from_sensor.transpose() * ContactNormalBody(sensor);
    const proto::Vector3& a = calibration.sensors(i).a();
    node.gain_a = Eigen::Vector3d(a.x(), a.y(), a.z());
  }
  return params;
}

dut_fw::GraspAdmittanceParams<double> FirmwareGraspParamsFor(const ScenarioConfig& config) {
  const GripperConfig& gripper = config.gripper;
  dut_fw::GraspAdmittanceParams<double> params;
  params.mass = gripper.controller_mass.value_or(params.mass);
  params.damping = gripper.controller_damping.value_or(params.damping);
  params.stiffness = gripper.controller_stiffness.value_or(params.stiffness);
  params.open_angle_rad = gripper.servo.min_angle_rad;
  params.closed_angle_rad = gripper.servo.max_angle_rad;
  params.force_feedback = gripper.force_feedback;
  // The firmware knows its own servo: how long a move to the reference angle takes before force
  // feedback may start integrating.
  params.servo_max_rate_rad_s = gripper.servo.max_rate_rad_s;
  params.servo_settle_s = 3 * gripper.servo.time_constant_s;
  return params;
}

DutFirmware FirmwareFor(const ScenarioConfig& config) {
  return {FirmwareParamsFor(config.vehicle), FirmwareTactileParamsFor(config),
          FirmwareGraspParamsFor(config), config.gripper.external_force_in_position_loop};
}

}  // namespace hilrig::host
