#include "host/scenario/scenario_config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "fixtures/objects/object_fixtures.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "rig/check.h"
#include "rig/clock.h"

namespace hilrig::host {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

Eigen::Vector3d ToEigen(const proto::Vector3& vector) {
  return {vector.x(), vector.y(), vector.z()};
}

// The spec's value when it set one, else the default.
template <typename T>
T Or(bool has, const T& value, const T& fallback) {
  return has ? value : fallback;
}

Integrator ResolveIntegrator(proto::Integrator integrator) {
  switch (integrator) {
    case proto::INTEGRATOR_SEMI_IMPLICIT_EULER:
      return Integrator::kSemiImplicitEuler;
    case proto::INTEGRATOR_MIDPOINT:
      return Integrator::kMidpoint;
    case proto::INTEGRATOR_DORMAND_PRINCE:
      return Integrator::kDormandPrince;
    default:
      return Integrator::kRk4;
  }
}

VehicleFidelity ResolveFidelity(proto::VehicleFidelity fidelity) {
  switch (fidelity) {
    case proto::VEHICLE_VERTICAL_1DOF:
      return VehicleFidelity::kVertical1Dof;
    case proto::VEHICLE_FIXED_STAND:
      return VehicleFidelity::kFixedStand;
    default:
      return VehicleFidelity::kFull6Dof;
  }
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
  LandingGearParams& gear = params.landing_gear;
  gear.stiffness_n_per_m = Or(vehicle.has_landing_gear_stiffness_n_per_m(),
                              vehicle.landing_gear_stiffness_n_per_m(), gear.stiffness_n_per_m);
  gear.damping_n_s_per_m = Or(vehicle.has_landing_gear_damping_n_s_per_m(),
                              vehicle.landing_gear_damping_n_s_per_m(), gear.damping_n_s_per_m);
  params.gravity_m_s2 = Or(spec.environment().has_gravity_m_s2(), spec.environment().gravity_m_s2(),
                           params.gravity_m_s2);
  params.integrator = ResolveIntegrator(spec.models().integrator());
  params.integrator_tolerance =
      Or(spec.models().has_integrator_tolerance(), spec.models().integrator_tolerance(),
         params.integrator_tolerance);
  params.fidelity = ResolveFidelity(spec.models().vehicle());
  return params;
}

void ResolveSensors(const proto::Scenario& spec, ScenarioConfig& config) {
  const bool noise = spec.models().noise() == proto::NOISE_ON;
  // The IMU and VIO sample on physics ticks. Their defaults (1000 and 30 Hz) are capped at the
  // tick rate: a 500 Hz scene got 500 IMU samples a second with noise scaled for 1000 Hz (sqrt(2)
  // too much) and a report that said 1000 Hz.
  const double physics_rate_hz = PhysicsRateHz(spec.simulation());
  const proto::Imu& imu = spec.models().imu();
  config.imu.rate_hz =
      Or(imu.has_rate_hz(), imu.rate_hz(), std::min(config.imu.rate_hz, physics_rate_hz));
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
  config.imu.accel_range_m_s2 =
      Or(imu.has_accel_range_m_s2(), imu.accel_range_m_s2(), config.imu.accel_range_m_s2);
  config.imu.gyro_range_rad_s =
      Or(imu.has_gyro_range_rad_s(), imu.gyro_range_rad_s(), config.imu.gyro_range_rad_s);
  config.imu.noise_enabled = noise;

  const proto::Vio& vio = spec.models().vio();
  config.vio.rate_hz =
      Or(vio.has_rate_hz(), vio.rate_hz(), std::min(config.vio.rate_hz, physics_rate_hz));
  config.vio.latency_s = Or(vio.has_latency_s(), vio.latency_s(), config.vio.latency_s);
  config.vio.position_noise_m =
      Or(vio.has_position_noise_m(), vio.position_noise_m(), config.vio.position_noise_m);
  config.vio.attitude_noise_rad =
      Or(vio.has_attitude_noise_rad(), vio.attitude_noise_rad(), config.vio.attitude_noise_rad);
  config.vio.noise_enabled = noise;

  if (spec.environment().has_earth_field_world_t()) {
    config.earth_field.field_world_t = ToEigen(spec.environment().earth_field_world_t());
  }
  if (spec.environment().has_geodetic_origin()) {
    const proto::GeodeticOrigin& origin = spec.environment().geodetic_origin();
    config.navigation.origin = {origin.latitude_deg(), origin.longitude_deg(), origin.altitude_m()};
  }
  // The navigation sensors sample on ticks too, at most once per tick.
  NavigationSensorsConfig& navigation = config.navigation;
  for (double* rate_hz : {&navigation.magnetometer.rate_hz, &navigation.barometer.rate_hz,
                          &navigation.gnss.rate_hz}) {
    *rate_hz = std::min(*rate_hz, physics_rate_hz);
  }
  navigation.magnetometer.noise_enabled = noise;
  navigation.barometer.noise_enabled = noise;
  navigation.gnss.noise_enabled = noise;
}

void ResolveHallSensors(const proto::Scenario& spec, const std::string& spec_directory,
                        HallSensorConfig& hall) {
  const proto::Tactile& tactile = spec.models().tactile();
  const bool noise = spec.models().noise() == proto::NOISE_ON;
  TactileSensorParams base;
  base.earth_field_enabled = Or(tactile.has_earth_field(), tactile.earth_field(), true);
  base.silicone.damping_enabled =
      Or(tactile.has_silicone_damping(), tactile.silicone_damping(), true);
  base.silicone.stiffening_enabled =
      Or(tactile.has_silicone_stiffening(), tactile.silicone_stiffening(), false);
  base.chip.noise_enabled = noise && Or(tactile.has_chip_noise(), tactile.chip_noise(), true);
  base.chip.drift_enabled = Or(tactile.has_chip_drift(), tactile.chip_drift(), true);
  base.chip.saturation_enabled = Or(tactile.has_chip_saturation(), tactile.chip_saturation(), true);
  base.chip.encoding_enabled = Or(tactile.has_chip_encoding(), tactile.chip_encoding(), true);
  hall.tactile_enabled = tactile.enabled();
  // The pads sit on the gripper frame: chips at the frame's open radius plus the film standoff
  // (their positions move in as the frame closes; their orientations do not change).
  const GripperFrameParams frame;
  TactileRingGeometry ring;
  ring.radius_m = frame.open_radius_m + frame.film_standoff_m;
  ring.height_m = frame.height_m;
  ring.first_azimuth_rad = frame.first_azimuth_rad;
  hall.tactile = DefaultTactileLayout(base, ring);
  hall.reference = DefaultReferenceSensor();
  hall.reference.chip = base.chip;
  hall.reference.earth_field_enabled = base.earth_field_enabled;
  if (tactile.has_reference_position_m()) {
    hall.reference.position_body_m = ToEigen(tactile.reference_position_m());
  }
  hall.film_cross_talk = Or(tactile.has_film_cross_talk(), tactile.film_cross_talk(), false);
  hall.field_fidelity =
      Or(tactile.has_field_fidelity(), tactile.field_fidelity(), std::string(kDefaultFilmFidelity));
  hall.node_rate_hz = Or(tactile.has_node_rate_hz(), tactile.node_rate_hz(), kDefaultNodeRateHz);
  hall.temperature_c = Or(tactile.has_temperature_c(), tactile.temperature_c(), 25.0);
  hall.compensation = Or(tactile.has_compensation(), tactile.compensation(), true);
  hall.zeroing_s = Or(tactile.has_zeroing_s(), tactile.zeroing_s(), 1.0);
  hall.force_average_samples = Or(tactile.has_force_average_samples(),
                                  tactile.force_average_samples(), kDefaultForceAverageSamples);
  if (tactile.has_calibration_file()) {
    const std::filesystem::path file(tactile.calibration_file());
    hall.calibration_file = file.is_absolute()
                                ? file.string()
                                : (std::filesystem::path(spec_directory) / file).string();
  }
}

void ResolveSimulation(const proto::Simulation& simulation, ScenarioConfig& config) {
  config.duration_s = simulation.duration_s();
  const double physics_rate_hz = PhysicsRateHz(simulation);
  config.physics_step_ns = std::llround(1e9 / physics_rate_hz);
  config.control_every_ticks = static_cast<int>(
      std::lround(physics_rate_hz / Or(simulation.has_control_rate_hz(),
                                       simulation.control_rate_hz(), physics_rate_hz)));
  config.trace_every_ticks =
      static_cast<int>(std::lround(physics_rate_hz / TraceRateHz(simulation)));
  config.can_bitrate_bps = Or(simulation.has_can_bitrate_bps(), simulation.can_bitrate_bps(), 1e6);
  config.plant_substeps = static_cast<int>(
      Or(simulation.has_plant_substeps(), simulation.plant_substeps(), std::uint32_t{1}));
  config.dut_fault_stops_run = simulation.dut_fault() == proto::DUT_FAULT_STOP;
}

std::optional<double> OptionalOf(bool has, double value) {
  return has ? std::optional<double>(value) : std::nullopt;
}

void ResolveTiming(const proto::TimingEnvelopes& timing, ScenarioConfig& config) {
  TimingLimits& limits = config.timing;
  limits.loop_period_p99_max_s =
      OptionalOf(timing.has_loop_period_p99_max_s(), timing.loop_period_p99_max_s());
  limits.loop_period_max_s = OptionalOf(timing.has_loop_period_max_s(), timing.loop_period_max_s());
  limits.late_tick_fraction_max =
      OptionalOf(timing.has_late_tick_fraction_max(), timing.late_tick_fraction_max());
  limits.dut_latency_p99_max_s =
      OptionalOf(timing.has_dut_latency_p99_max_s(), timing.dut_latency_p99_max_s());
  limits.dut_commands_missed_fraction_max = OptionalOf(
      timing.has_dut_commands_missed_fraction_max(), timing.dut_commands_missed_fraction_max());
  config.late_threshold_ns = timing.has_late_threshold_s()
                                 ? std::llround(timing.late_threshold_s() * 1e9)
                                 : config.physics_step_ns;
}

void ResolveTarget(const proto::TargetEnvelopes& target, ScenarioConfig& config) {
  config.target.work_p99_fraction_max =
      OptionalOf(target.has_work_p99_fraction_max(), target.work_p99_fraction_max());
  config.target.work_max_fraction_max =
      OptionalOf(target.has_work_max_fraction_max(), target.work_max_fraction_max());
}

EnvelopeSpec ResolveEnvelope(const proto::Envelope& envelope) {
  EnvelopeSpec resolved;
  resolved.name = envelope.name();
  resolved.signal = envelope.signal();
  if (envelope.has_pad()) resolved.pad = envelope.pad();
  resolved.lower = OptionalOf(envelope.has_lower(), envelope.lower());
  resolved.upper = OptionalOf(envelope.has_upper(), envelope.upper());
  resolved.from_s = Or(envelope.has_from_s(), envelope.from_s(), 0.0);
  resolved.until_s = OptionalOf(envelope.has_until_s(), envelope.until_s());
  resolved.expect =
      envelope.expect() == proto::FAIL ? EnvelopeVerdict::kFail : EnvelopeVerdict::kPass;
  resolved.abort_on_violation = envelope.abort_on_violation();
  resolved.mean_over_s = OptionalOf(envelope.has_mean_over_s(), envelope.mean_over_s());
  return resolved;
}

ObjectPlacement ResolveObject(const proto::GraspObject& spec, double at_s,
                              double default_stand_height_m) {
  auto fixture = fixtures::ObjectFixture(spec.fixture());
  HILRIG_CHECK(fixture.ok(), "object fixtures are validated before the run");
  ObjectPlacement placement;
  placement.at_s = at_s;
  placement.fixture = spec.fixture();
  placement.object = WithStiffnessScale(
      fixture.value(), Or(spec.has_stiffness_scale(), spec.stiffness_scale(), 1.0));
  placement.object.mass_kg = Or(spec.has_mass_kg(), spec.mass_kg(), placement.object.mass_kg);
  if (spec.has_damage_force_n()) {
    placement.object.damage_force_n = spec.damage_force_n();
    if (placement.object.damage_mode == DamageMode::kNone) {
      placement.object.damage_mode = DamageMode::kCrush;
    }
  }
  placement.stand_height_m =
      Or(spec.has_stand_height_m(), spec.stand_height_m(), default_stand_height_m);
  return placement;
}

void ResolveGripper(const proto::Scenario& spec, GripperConfig& gripper) {
  gripper.enabled = spec.has_object();
  const proto::Gripper& hardware = spec.models().gripper();
  gripper.servo.stall_torque_nm =
      Or(hardware.has_stall_torque_nm(), hardware.stall_torque_nm(), gripper.servo.stall_torque_nm);
  gripper.servo.max_rate_rad_s =
      Or(hardware.has_max_rate_rad_s(), hardware.max_rate_rad_s(), gripper.servo.max_rate_rad_s);
  gripper.servo.time_constant_s =
      Or(hardware.has_servo_time_constant_s(), hardware.servo_time_constant_s(),
         gripper.servo.time_constant_s);
  const proto::GraspController& controller = spec.grasp_controller();
  if (controller.has_mass()) gripper.controller_mass = controller.mass();
  if (controller.has_damping()) gripper.controller_damping = controller.damping();
  if (controller.has_stiffness()) gripper.controller_stiffness = controller.stiffness();
  gripper.force_feedback = Or(controller.has_force_feedback(), controller.force_feedback(), true);
  gripper.external_force_in_position_loop = Or(controller.has_external_force_in_position_loop(),
                                               controller.external_force_in_position_loop(), true);
  if (!gripper.enabled) return;
  const double default_stand_m = spec.vehicle().initial_position_m().z();
  gripper.objects.push_back(ResolveObject(spec.object(), 0.0, default_stand_m));
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
    } else if (entry.has_grasp()) {
      const proto::Grasp& grasp = entry.grasp();
      GraspCommandEvent event{entry.at_s(), !grasp.open(), grasp.force_n(), std::nullopt};
      if (grasp.has_reference_angle_rad()) event.reference_angle_rad = grasp.reference_angle_rad();
      config.gripper.grasps.push_back(event);
    } else if (entry.has_pour()) {
      config.gripper.pours.push_back(
          {entry.at_s(), entry.pour().mass_kg(), entry.pour().duration_s()});
    } else if (entry.has_stray_field()) {
      const proto::StrayField& stray = entry.stray_field();
      config.hall_sensors.stray_fields.push_back({entry.at_s(), stray.duration_s(),
                                                  static_cast<std::uint8_t>(stray.node()),
                                                  ToEigen(stray.field_sensor_t())});
    } else if (entry.has_remove_support()) {
      config.gripper.support_removals_s.push_back(entry.at_s());
    } else if (entry.has_present_object()) {
      config.gripper.objects.push_back(ResolveObject(entry.present_object(), entry.at_s(),
                                                     spec.vehicle().initial_position_m().z()));
    }
  }
}

}  // namespace

ScenarioConfig ResolveScenario(const proto::Scenario& spec,
                               std::optional<std::uint64_t> seed_override,
                               const std::string& spec_directory) {
  ScenarioConfig config;
  config.name = spec.name();
  config.seed = seed_override.value_or(spec.has_seed() ? spec.seed() : 1);
  config.vehicle = ResolveVehicle(spec);
  ResolveSensors(spec, config);
  ResolveHallSensors(spec, spec_directory, config.hall_sensors);
  ResolveGripper(spec, config.gripper);
  ResolveSimulation(spec.simulation(), config);
  ResolveTiming(spec.timing(), config);
  ResolveTarget(spec.target(), config);

  const double initial_yaw_rad = spec.vehicle().initial_yaw_deg() * kDegToRad;
  config.initial_reference.position_m = ToEigen(spec.vehicle().initial_position_m());
  config.initial_reference.yaw_rad = initial_yaw_rad;
  ResolveTimeline(spec, config);
  const auto by_time = [](const auto& a, const auto& b) { return a.at_s < b.at_s; };
  std::stable_sort(config.gripper.objects.begin(), config.gripper.objects.end(), by_time);
  std::stable_sort(config.gripper.grasps.begin(), config.gripper.grasps.end(), by_time);
  std::sort(config.gripper.support_removals_s.begin(), config.gripper.support_removals_s.end());
  for (const proto::Envelope& envelope : spec.envelopes())
    config.envelopes.push_back(ResolveEnvelope(envelope));
  return config;
}

std::uint64_t TotalTicks(const ScenarioConfig& config) {
  return static_cast<std::uint64_t>(
      std::llround(config.duration_s * 1e9 / static_cast<double>(config.physics_step_ns)));
}

double ControlPeriodS(const ScenarioConfig& config) {
  return rig::SecondsFromNs(config.physics_step_ns) *
         static_cast<double>(config.control_every_ticks);
}

std::uint64_t CompletedRunTraceSamples(const ScenarioConfig& config) {
  return TotalTicks(config) / static_cast<std::uint64_t>(config.trace_every_ticks);
}

double PhysicsRateHz(const proto::Simulation& simulation) {
  return Or(simulation.has_physics_rate_hz(), simulation.physics_rate_hz(), kDefaultPhysicsRateHz);
}

double TraceRateHz(const proto::Simulation& simulation) {
  return Or(simulation.has_trace_rate_hz(), simulation.trace_rate_hz(), kDefaultTraceRateHz);
}

}  // namespace hilrig::host
