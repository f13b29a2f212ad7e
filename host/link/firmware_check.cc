#include "host/link/firmware_check.h"

#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// Keeps the first problem found; later checks are no-ops once there is one.
class Checker {
 public:
  void Positive(const std::string& name, double value) {
    Require(name, value, std::isfinite(value) && value > 0, "must be finite and > 0");
  }
  void NonNegative(const std::string& name, double value) {
    Require(name, value, std::isfinite(value) && value >= 0, "must be finite and >= 0");
  }
  void Finite(const std::string& name, double value) {
    Require(name, value, std::isfinite(value), "must be finite");
  }
  void NonZero(const std::string& name, double value) {
    Require(name, value, std::isfinite(value) && value != 0, "must be finite and not 0");
  }
  void Within(const std::string& name, double value, double low, double high) {
    Require(name, value, std::isfinite(value) && value >= low && value <= high,
            "must lie in [" + rig::NumberText(low) + ", " + rig::NumberText(high) + "]");
  }
  void AtLeast(const std::string& name, double value, const std::string& other, double low) {
    Require(name, value, value >= low,
            "must be at least " + other + " (" + rig::NumberText(low) + ")");
  }
  template <typename Check>
  void Each(const std::string& name, const Eigen::Vector3d& values, Check check) {
    static constexpr const char* kAxes[] = {".x", ".y", ".z"};
    for (int i = 0; i < 3; ++i) (this->*check)(name + kAxes[i], values[i]);
  }
  void AllFinite(const std::string& name, const Eigen::Matrix3d& values) {
    for (int i = 0; i < 9; ++i) {
      Finite(name + "[" + std::to_string(i) + "]", values(i / 3, i % 3));
    }
  }
  void Fail(std::string problem) {
    if (!problem_) problem_ = std::move(problem);
  }

  rig::Result<void> Result() const {
    if (problem_) return rig::MakeError(*problem_);
    return {};
  }

 private:
  void Require(const std::string& name, double value, bool ok, const std::string& rule) {
    if (!ok) Fail(name + " is " + rig::NumberText(value) + ": " + rule);
  }

  std::optional<std::string> problem_;
};

void CheckFlight(const dut_fw::FlightControllerParams<double>& p, Checker& c) {
  c.Each("flight.admittance.mass_kg", p.admittance.mass_kg, &Checker::Positive);
  c.Each("flight.admittance.damping_n_s_per_m", p.admittance.damping_n_s_per_m,
         &Checker::NonNegative);
  c.Each("flight.admittance.stiffness_n_per_m", p.admittance.stiffness_n_per_m,
         &Checker::NonNegative);
  c.Each("flight.position.kp_per_s2", p.position.kp_per_s2, &Checker::NonNegative);
  c.Each("flight.position.kv_per_s", p.position.kv_per_s, &Checker::NonNegative);
  c.Positive("flight.position.mass_kg", p.position.mass_kg);
  c.Positive("flight.position.gravity_m_s2", p.position.gravity_m_s2);
  c.Within("flight.position.max_tilt_rad", p.position.max_tilt_rad, 0, std::numbers::pi / 2);
  c.NonNegative("flight.position.min_collective_thrust_n", p.position.min_collective_thrust_n);
  c.Positive("flight.position.max_collective_thrust_n", p.position.max_collective_thrust_n);
  c.AtLeast("flight.position.max_collective_thrust_n", p.position.max_collective_thrust_n,
            "min_collective_thrust_n", p.position.min_collective_thrust_n);
  c.Each("flight.attitude.k_r_per_s", p.attitude.k_r_per_s, &Checker::NonNegative);
  c.Each("flight.attitude.k_p_nm_s", p.attitude.k_p_nm_s, &Checker::NonNegative);
  c.Each("flight.attitude.k_i_nm", p.attitude.k_i_nm, &Checker::NonNegative);
  c.Each("flight.attitude.k_d_nm_s2", p.attitude.k_d_nm_s2, &Checker::NonNegative);
  c.Each("flight.attitude.max_rate_rad_s", p.attitude.max_rate_rad_s, &Checker::Positive);
  c.Each("flight.attitude.integral_limit_rad", p.attitude.integral_limit_rad,
         &Checker::NonNegative);
  c.Positive("flight.attitude.derivative_cutoff_hz", p.attitude.derivative_cutoff_hz);
  c.Each("flight.attitude.inertia_kg_m2", p.attitude.inertia_kg_m2, &Checker::NonNegative);
  c.Positive("flight.mixer.arm_length_m", p.mixer.arm_length_m);
  c.NonNegative("flight.mixer.torque_per_thrust_m", p.mixer.torque_per_thrust_m);
  c.Positive("flight.mixer.max_thrust_per_rotor_n", p.mixer.max_thrust_per_rotor_n);
  c.Within("flight.estimator.position_gain", p.estimator.position_gain, 0, 1);
  c.NonNegative("flight.estimator.velocity_gain", p.estimator.velocity_gain);
  c.NonNegative("flight.estimator.accel_bias_gain", p.estimator.accel_bias_gain);
  c.Within("flight.estimator.attitude_gain", p.estimator.attitude_gain, 0, 1);
  c.NonNegative("flight.estimator.gyro_bias_gain", p.estimator.gyro_bias_gain);
  c.Positive("flight.estimator.gravity_m_s2", p.estimator.gravity_m_s2);
  c.Positive("flight.estimator.nominal_vio_period_s", p.estimator.nominal_vio_period_s);
  c.NonNegative("flight.estimator.max_gyro_bias_rad_s", p.estimator.max_gyro_bias_rad_s);
  c.NonNegative("flight.estimator.max_accel_bias_m_s2", p.estimator.max_accel_bias_m_s2);
}

void CheckTactile(const dut_fw::TactileProcessorParams<double>& p, Checker& c) {
  unsigned ids_seen = 0;
  for (std::size_t i = 0; i < p.nodes.size(); ++i) {
    const dut_fw::TactileNodeConfig<double>& node = p.nodes[i];
    const std::string name = "tactile.nodes[" + std::to_string(i) + "]";
    const std::string id = name + ".node_id is " + std::to_string(node.node_id);
    if (node.node_id < 1 || node.node_id > tactile_bus::kTactileNodeCount) {
      c.Fail(id + ": must lie in [1, " + std::to_string(tactile_bus::kTactileNodeCount) + "]");
    } else if ((ids_seen & (1u << node.node_id)) != 0) {
      c.Fail(id + ": used by an earlier node");
    } else {
      ids_seen |= 1u << node.node_id;
    }
    c.AllFinite(name + ".rotation_sensor_from_reference", node.rotation_sensor_from_reference);
    c.AllFinite(name + ".rotation_body_from_sensor", node.rotation_body_from_sensor);
    c.Each(name + ".contact_normal_sensor", node.contact_normal_sensor, &Checker::Finite);
    c.Each(name + ".gain_a", node.gain_a, &Checker::Finite);
  }
  c.NonZero("tactile.film.k1", p.film.k1);
  c.Finite("tactile.film.c1", p.film.c1);
  c.NonZero("tactile.film.k2", p.film.k2);
  c.Finite("tactile.film.c2", p.film.c2);
  if (p.zeroing_samples == 0) c.Fail("tactile.zeroing_samples is 0: must be at least 1");
  if (p.force_average_samples < 1 || p.force_average_samples > dut_fw::kMaxForceAverageSamples) {
    c.Fail("tactile.force_average_samples is " + std::to_string(p.force_average_samples) +
           ": must lie in [1, " + std::to_string(dut_fw::kMaxForceAverageSamples) + "]");
  }
  if (p.max_reference_age_ns <= 0) {
    c.Fail("tactile.max_reference_age_ns is " + std::to_string(p.max_reference_age_ns) +
           ": must be > 0");
  }
  if (p.max_sample_age_ns <= 0) {
    c.Fail("tactile.max_sample_age_ns is " + std::to_string(p.max_sample_age_ns) + ": must be > 0");
  }
}

void CheckGrasp(const dut_fw::GraspAdmittanceParams<double>& p, Checker& c) {
  c.Positive("grasp.mass", p.mass);
  c.NonNegative("grasp.damping", p.damping);
  c.NonNegative("grasp.stiffness", p.stiffness);
  c.Finite("grasp.open_angle_rad", p.open_angle_rad);
  c.Finite("grasp.closed_angle_rad", p.closed_angle_rad);
  if (p.closed_angle_rad <= p.open_angle_rad) {
    c.Fail("grasp.closed_angle_rad is " + rig::NumberText(p.closed_angle_rad) +
           ": must be above open_angle_rad (" + rig::NumberText(p.open_angle_rad) + ")");
  }
  // Infinite is the firmware's "no travel hold".
  if (!(p.servo_max_rate_rad_s > 0)) {
    c.Fail("grasp.servo_max_rate_rad_s is " + rig::NumberText(p.servo_max_rate_rad_s) +
           ": must be > 0");
  }
  c.NonNegative("grasp.servo_settle_s", p.servo_settle_s);
}

}  // namespace

rig::Result<void> CheckDutFirmware(const DutFirmware& firmware) {
  Checker checker;
  CheckFlight(firmware.flight, checker);
  if (firmware.tactile) CheckTactile(*firmware.tactile, checker);
  CheckGrasp(firmware.grasp, checker);
  return checker.Result();
}

}  // namespace hilrig::host
