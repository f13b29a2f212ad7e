#include "host/link/dut_config_codec.h"

#include <cmath>
#include <string>

#include "host/link/firmware_check.h"

namespace hilrig::host {
namespace {

void PutVector(const Eigen::Vector3d& in, proto::Vector3* out) {
  out->set_x(in.x());
  out->set_y(in.y());
  out->set_z(in.z());
}

Eigen::Vector3d GetVector(const proto::Vector3& in) { return {in.x(), in.y(), in.z()}; }

void PutMatrix(const Eigen::Matrix3d& in, proto::Matrix3* out) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out->add_row_major(in(r, c));
  }
}

rig::Result<Eigen::Matrix3d> GetMatrix(const proto::Matrix3& in, const std::string& what) {
  if (in.row_major_size() != 9) {
    return rig::MakeError(what + " has " + std::to_string(in.row_major_size()) +
                          " values instead of 9");
  }
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out(r, c) = in.row_major(3 * r + c);
  }
  return out;
}

proto::FlightFirmware ToProto(const dut_fw::FlightControllerParams<double>& p) {
  proto::FlightFirmware out;
  PutVector(p.admittance.mass_kg, out.mutable_admittance_mass_kg());
  PutVector(p.admittance.damping_n_s_per_m, out.mutable_admittance_damping_n_s_per_m());
  PutVector(p.admittance.stiffness_n_per_m, out.mutable_admittance_stiffness_n_per_m());
  PutVector(p.position.kp_per_s2, out.mutable_position_kp_per_s2());
  PutVector(p.position.kv_per_s, out.mutable_position_kv_per_s());
  out.set_position_mass_kg(p.position.mass_kg);
  out.set_position_gravity_m_s2(p.position.gravity_m_s2);
  out.set_position_max_tilt_rad(p.position.max_tilt_rad);
  out.set_position_min_collective_thrust_n(p.position.min_collective_thrust_n);
  out.set_position_max_collective_thrust_n(p.position.max_collective_thrust_n);
  PutVector(p.attitude.k_r_per_s, out.mutable_attitude_k_r_per_s());
  PutVector(p.attitude.k_p_nm_s, out.mutable_attitude_k_p_nm_s());
  PutVector(p.attitude.k_i_nm, out.mutable_attitude_k_i_nm());
  PutVector(p.attitude.k_d_nm_s2, out.mutable_attitude_k_d_nm_s2());
  PutVector(p.attitude.max_rate_rad_s, out.mutable_attitude_max_rate_rad_s());
  PutVector(p.attitude.integral_limit_rad, out.mutable_attitude_integral_limit_rad());
  out.set_attitude_derivative_cutoff_hz(p.attitude.derivative_cutoff_hz);
  PutVector(p.attitude.inertia_kg_m2, out.mutable_attitude_inertia_kg_m2());
  out.set_mixer_arm_length_m(p.mixer.arm_length_m);
  out.set_mixer_torque_per_thrust_m(p.mixer.torque_per_thrust_m);
  out.set_mixer_max_thrust_per_rotor_n(p.mixer.max_thrust_per_rotor_n);
  out.set_estimator_position_gain(p.estimator.position_gain);
  out.set_estimator_velocity_gain(p.estimator.velocity_gain);
  out.set_estimator_accel_bias_gain(p.estimator.accel_bias_gain);
  out.set_estimator_attitude_gain(p.estimator.attitude_gain);
  out.set_estimator_gyro_bias_gain(p.estimator.gyro_bias_gain);
  out.set_estimator_gravity_m_s2(p.estimator.gravity_m_s2);
  out.set_estimator_nominal_vio_period_s(p.estimator.nominal_vio_period_s);
  out.set_estimator_max_gyro_bias_rad_s(p.estimator.max_gyro_bias_rad_s);
  out.set_estimator_max_accel_bias_m_s2(p.estimator.max_accel_bias_m_s2);
  out.set_load_feedforward(p.load_feedforward);
  return out;
}

dut_fw::FlightControllerParams<double> FromProto(const proto::FlightFirmware& in) {
  dut_fw::FlightControllerParams<double> p;
  p.admittance.mass_kg = GetVector(in.admittance_mass_kg());
  p.admittance.damping_n_s_per_m = GetVector(in.admittance_damping_n_s_per_m());
  p.admittance.stiffness_n_per_m = GetVector(in.admittance_stiffness_n_per_m());
  p.position.kp_per_s2 = GetVector(in.position_kp_per_s2());
  p.position.kv_per_s = GetVector(in.position_kv_per_s());
  p.position.mass_kg = in.position_mass_kg();
  p.position.gravity_m_s2 = in.position_gravity_m_s2();
  p.position.max_tilt_rad = in.position_max_tilt_rad();
  p.position.min_collective_thrust_n = in.position_min_collective_thrust_n();
  p.position.max_collective_thrust_n = in.position_max_collective_thrust_n();
  p.attitude.k_r_per_s = GetVector(in.attitude_k_r_per_s());
  p.attitude.k_p_nm_s = GetVector(in.attitude_k_p_nm_s());
  p.attitude.k_i_nm = GetVector(in.attitude_k_i_nm());
  p.attitude.k_d_nm_s2 = GetVector(in.attitude_k_d_nm_s2());
  p.attitude.max_rate_rad_s = GetVector(in.attitude_max_rate_rad_s());
  p.attitude.integral_limit_rad = GetVector(in.attitude_integral_limit_rad());
  p.attitude.derivative_cutoff_hz = in.attitude_derivative_cutoff_hz();
  p.attitude.inertia_kg_m2 = GetVector(in.attitude_inertia_kg_m2());
  p.mixer.arm_length_m = in.mixer_arm_length_m();
  p.mixer.torque_per_thrust_m = in.mixer_torque_per_thrust_m();
  p.mixer.max_thrust_per_rotor_n = in.mixer_max_thrust_per_rotor_n();
  p.estimator.position_gain = in.estimator_position_gain();
  p.estimator.velocity_gain = in.estimator_velocity_gain();
  p.estimator.accel_bias_gain = in.estimator_accel_bias_gain();
  p.estimator.attitude_gain = in.estimator_attitude_gain();
  p.estimator.gyro_bias_gain = in.estimator_gyro_bias_gain();
  p.estimator.gravity_m_s2 = in.estimator_gravity_m_s2();
  p.estimator.nominal_vio_period_s = in.estimator_nominal_vio_period_s();
  p.estimator.max_gyro_bias_rad_s = in.estimator_max_gyro_bias_rad_s();
  p.estimator.max_accel_bias_m_s2 = in.estimator_max_accel_bias_m_s2();
  p.load_feedforward = in.load_feedforward();
  return p;
}

proto::TactileFirmware ToProto(const dut_fw::TactileProcessorParams<double>& p) {
  proto::TactileFirmware out;
  for (const dut_fw::TactileNodeConfig<double>& node : p.nodes) {
    proto::TactileNodeFirmware* n = out.add_nodes();
    n->set_node_id(node.node_id);
    PutMatrix(node.rotation_sensor_from_reference, n->mutable_rotation_sensor_from_reference());
    PutMatrix(node.rotation_body_from_sensor, n->mutable_rotation_body_from_sensor());
    PutVector(node.contact_normal_sensor, n->mutable_contact_normal_sensor());
    PutVector(node.gain_a, n->mutable_gain_a());
  }
  out.set_film_k1(p.film.k1);
  out.set_film_c1(p.film.c1);
  out.set_film_k2(p.film.k2);
  out.set_film_c2(p.film.c2);
  out.set_chip_gain_sel(p.chip_setting.gain_sel);
  out.set_chip_resolution(p.chip_setting.resolution);
  out.set_zeroing_samples(p.zeroing_samples);
  out.set_compensation_enabled(p.compensation_enabled);
  out.set_max_reference_age_ns(p.max_reference_age_ns);
  out.set_max_sample_age_ns(p.max_sample_age_ns);
  out.set_force_average_samples(p.force_average_samples);
  return out;
}

rig::Result<dut_fw::TactileProcessorParams<double>> FromProto(const proto::TactileFirmware& in) {
  dut_fw::TactileProcessorParams<double> p;
  if (in.nodes_size() != static_cast<int>(p.nodes.size())) {
    return rig::MakeError("tactile firmware with " + std::to_string(in.nodes_size()) +
                          " nodes instead of " + std::to_string(p.nodes.size()));
  }
  for (std::size_t i = 0; i < p.nodes.size(); ++i) {
    const proto::TactileNodeFirmware& n = in.nodes(static_cast<int>(i));
    const std::string what = "tactile node " + std::to_string(i);
    if (n.node_id() > 255) return rig::MakeError(what + " id " + std::to_string(n.node_id()));
    auto from_reference = GetMatrix(n.rotation_sensor_from_reference(), what + " rotation");
    auto body_from_sensor = GetMatrix(n.rotation_body_from_sensor(), what + " mounting");
    if (!from_reference) return from_reference.error();
    if (!body_from_sensor) return body_from_sensor.error();
    dut_fw::TactileNodeConfig<double>& node = p.nodes[i];
    node.node_id = static_cast<std::uint8_t>(n.node_id());
    node.rotation_sensor_from_reference = from_reference.value();
    node.rotation_body_from_sensor = body_from_sensor.value();
    node.contact_normal_sensor = GetVector(n.contact_normal_sensor());
    node.gain_a = GetVector(n.gain_a());
  }
  p.film = {in.film_k1(), in.film_c1(), in.film_k2(), in.film_c2()};
  if (in.chip_gain_sel() > dut_fw::kMlx90393MaxGainSel ||
      in.chip_resolution() > dut_fw::kMlx90393MaxResolution) {
    return rig::MakeError("tactile firmware with an invalid chip setting (gain_sel " +
                          std::to_string(in.chip_gain_sel()) + ", resolution " +
                          std::to_string(in.chip_resolution()) + ")");
  }
  p.chip_setting = {static_cast<std::uint8_t>(in.chip_gain_sel()),
                    static_cast<std::uint8_t>(in.chip_resolution())};
  p.zeroing_samples = in.zeroing_samples();
  p.compensation_enabled = in.compensation_enabled();
  p.max_reference_age_ns = in.max_reference_age_ns();
  p.max_sample_age_ns = in.max_sample_age_ns();
  // Absent (0) is a peer that does not filter.
  p.force_average_samples = in.force_average_samples() == 0 ? 1 : in.force_average_samples();
  return p;
}

proto::GraspFirmware ToProto(const dut_fw::GraspAdmittanceParams<double>& p) {
  proto::GraspFirmware out;
  out.set_mass(p.mass);
  out.set_damping(p.damping);
  out.set_stiffness(p.stiffness);
  out.set_open_angle_rad(p.open_angle_rad);
  out.set_closed_angle_rad(p.closed_angle_rad);
  out.set_force_feedback(p.force_feedback);
  out.set_servo_max_rate_rad_s(p.servo_max_rate_rad_s);
  out.set_servo_settle_s(p.servo_settle_s);
  return out;
}

dut_fw::GraspAdmittanceParams<double> FromProto(const proto::GraspFirmware& in) {
  dut_fw::GraspAdmittanceParams<double> p;
  p.mass = in.mass();
  p.damping = in.damping();
  p.stiffness = in.stiffness();
  p.open_angle_rad = in.open_angle_rad();
  p.closed_angle_rad = in.closed_angle_rad();
  p.force_feedback = in.force_feedback();
  p.servo_max_rate_rad_s = in.servo_max_rate_rad_s();
  p.servo_settle_s = in.servo_settle_s();
  return p;
}

}  // namespace

proto::DutConfig ToDutConfig(const DutFirmware& firmware, double control_period_s) {
  proto::DutConfig config;
  *config.mutable_flight() = ToProto(firmware.flight);
  if (firmware.tactile) *config.mutable_tactile() = ToProto(*firmware.tactile);
  *config.mutable_grasp() = ToProto(firmware.grasp);
  config.set_external_force_in_position_loop(firmware.external_force_in_position_loop);
  config.set_control_period_s(control_period_s);
  return config;
}

rig::Result<DutSetup> FromDutConfig(const proto::DutConfig& config) {
  if (!std::isfinite(config.control_period_s()) || config.control_period_s() <= 0) {
    return rig::MakeError("dut config with control period " +
                          std::to_string(config.control_period_s()) +
                          " s; it must be positive and finite");
  }
  if (!config.has_flight() || !config.has_grasp()) {
    return rig::MakeError("dut config without flight or grasp firmware");
  }
  DutSetup setup;
  setup.control_period_s = config.control_period_s();
  setup.firmware.flight = FromProto(config.flight());
  if (config.has_tactile()) {
    auto tactile = FromProto(config.tactile());
    if (!tactile) return tactile.error();
    setup.firmware.tactile = tactile.value();
  }
  setup.firmware.grasp = FromProto(config.grasp());
  setup.firmware.external_force_in_position_loop = config.external_force_in_position_loop();
  if (auto valid = CheckDutFirmware(setup.firmware); !valid) return valid.error();
  return setup;
}

}  // namespace hilrig::host
