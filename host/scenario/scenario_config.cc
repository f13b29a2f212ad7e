#include "host/scenario/scenario_config.h"

#include <cmath>
#include <numbers>

namespace hilrig::host {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

Eigen::Vector3d ToEigen(const proto::Vector3& vector) {
  return {vector.x(), vector.y(), vector.z()};
}

template <typename T>
double Or(bool has, T value, double fallback) {
  return has ? static_cast<double>(value) : fallback;
}

QuadrotorParams ResolveVehicle(const proto::Scenario& spec) {
  const proto::Vehicle& vehicle = spec.vehicle();
  QuadrotorParams params;
  params.body.mass_kg = Or(vehicle.has_mass_kg(), vehicle.mass_kg(), params.body.mass_kg);
  if (vehicle.has_inertia_kg_m2()) params.body.inertia_kg_m2 = ToEigen(vehicle.inertia_kg_m2());
  auto& rotors = params.rotors;
  rotors.arm_length_m = Or(vehicle.has_arm_length_m(), vehicle.arm_length_m(), rotors.arm_length_m);
  rotors.max_thrust_n = Or(vehicle.has_max_thrust_per_rotor_n(), vehicle.max_thrust_per_rotor_n(),
                           rotors.max_thrust_n);
  rotors.torque_per_thrust_m = Or(vehicle.has_torque_per_thrust_m(), vehicle.torque_per_thrust_m(),
                                  rotors.torque_per_thrust_m);
  rotors.time_constant_s = Or(vehicle.has_rotor_time_constant_s(), vehicle.rotor_time_constant_s(),
                              rotors.time_constant_s);
  rotors.instantaneous = spec.models().rotors() == proto::ROTORS_INSTANTANEOUS;
  params.linear_drag_n_s_per_m = Or(vehicle.has_linear_drag_n_s_per_m(),
                                    vehicle.linear_drag_n_s_per_m(), params.linear_drag_n_s_per_m);
  params.gravity_m_s2 = Or(spec.environment().has_gravity_m_s2(), spec.environment().gravity_m_s2(),
                           params.gravity_m_s2);
  params.integrator = spec.models().integrator() == proto::INTEGRATOR_SEMI_IMPLICIT_EULER
                          ? Integrator::kSemiImplicitEuler
                          : Integrator::kRk4;
  return params;
}

void ResolveSensors(const proto::Scenario& spec, ScenarioConfig& config) {
  const bool noise = spec.models().noise() == proto::NOISE_ON;
  const proto::Imu& imu = spec.models().imu();
  config.imu.rate_hz = Or(imu.has_rate_hz(), imu.rate_hz(), config.imu.rate_hz);
  config.imu.gyro_noise_density_rad_s_sqrt_hz =
      Or(imu.has_gyro_noise_density_rad_s_sqrt_hz(), imu.gyro_noise_density_rad_s_sqrt_hz(),
         config.imu.gyro_noise_density_rad_s_sqrt_hz);
  config.imu.gyro_bias_sigma_rad_s =
      Or(imu.has_gyro_bias_sigma_rad_s(), imu.gyro_bias_sigma_rad_s(),
         config.imu.gyro_bias_sigma_rad_s);
  config.imu.accel_noise_density_m_s2_sqrt_hz =
      Or(imu.has_accel_noise_density_m_s2_sqrt_hz(), imu.accel_noise_density_m_s2_sqrt_hz(),
         config.imu.accel_noise_density_m_s2_sqrt_hz);
  config.imu.accel_bias_sigma_m_s2 =
      Or(imu.has_accel_bias_sigma_m_s2(), imu.accel_bias_sigma_m_s2(),
         config.imu.accel_bias_sigma_m_s2);
  config.imu.noise_enabled = noise;

  const proto::Vio& vio = spec.models().vio();
  config.vio.rate_hz = Or(vio.has_rate_hz(), vio.rate_hz(), config.vio.rate_hz);
  config.vio.latency_s = Or(vio.has_latency_s(), vio.latency_s(), config.vio.latency_s);
  config.vio.position_noise_m =
      Or(vio.has_position_noise_m(), vio.position_noise_m(), config.vio.position_noise_m);
  config.vio.attitude_noise_rad =
      Or(vio.has_attitude_noise_rad(), vio.attitude_noise_rad(), config.vio.attitude_noise_rad);
  config.vio.noise_enabled = noise;

  const proto::Magnetometer& magnetometer = spec.models().reference_magnetometer();
  config.magnetometer.rate_hz =
      Or(magnetometer.has_rate_hz(), magnetometer.rate_hz(), config.magnetometer.rate_hz);
  config.magnetometer.noise_t =
      Or(magnetometer.has_noise_t(), magnetometer.noise_t(), config.magnetometer.noise_t);
  config.magnetometer.noise_enabled = noise;
  if (spec.environment().has_earth_field_world_t()) {
    config.earth_field.field_world_t = ToEigen(spec.environment().earth_field_world_t());
  }
}

void ResolveSimulation(const proto::Simulation& simulation, ScenarioConfig& config) {
  config.duration_s = simulation.duration_s();
  const double physics_rate_hz =
      Or(simulation.has_physics_rate_hz(), simulation.physics_rate_hz(), 1000.0);
  config.physics_step_ns = std::llround(1e9 / physics_rate_hz);
  config.control_every_ticks = static_cast<int>(
      std::lround(physics_rate_hz / Or(simulation.has_control_rate_hz(),
                                       simulation.control_rate_hz(), physics_rate_hz)));
  config.trace_every_ticks = static_cast<int>(std::lround(
      physics_rate_hz / Or(simulation.has_trace_rate_hz(), simulation.trace_rate_hz(), 100.0)));
  config.can_bitrate_bps = Or(simulation.has_can_bitrate_bps(), simulation.can_bitrate_bps(), 1e6);
}

void ResolveTimeline(const proto::Scenario& spec, ScenarioConfig& config) {
  double yaw_rad = config.initial_reference.yaw_rad;
  for (const proto::TimelineEntry& entry : spec.timeline()) {
    if (entry.has_setpoint()) {
      const proto::Setpoint& setpoint = entry.setpoint();
      if (setpoint.has_yaw_deg()) yaw_rad = setpoint.yaw_deg() * kDegToRad;
      config.setpoints.push_back(
          {entry.at_s(), ToEigen(setpoint.position_m()), yaw_rad, setpoint.transition_s()});
    } else if (entry.has_disturbance()) {
      config.disturbances.push_back({entry.at_s(), entry.disturbance().duration_s(),
                                     ToEigen(entry.disturbance().force_world_n())});
    }
  }
}

}  // namespace

ScenarioConfig ResolveScenario(const proto::Scenario& spec,
                               std::optional<std::uint64_t> seed_override) {
  ScenarioConfig config;
  config.name = spec.name();
  config.seed = seed_override.value_or(spec.has_seed() ? spec.seed() : 1);
  config.vehicle = ResolveVehicle(spec);
  ResolveSensors(spec, config);
  ResolveSimulation(spec.simulation(), config);

  const double initial_yaw_rad = spec.vehicle().initial_yaw_deg() * kDegToRad;
  config.initial_reference.position_m = ToEigen(spec.vehicle().initial_position_m());
  config.initial_reference.yaw_rad = initial_yaw_rad;
  ResolveTimeline(spec, config);
  config.envelopes.assign(spec.envelopes().begin(), spec.envelopes().end());
  config.models = spec.models();
  return config;
}

}  // namespace hilrig::host
