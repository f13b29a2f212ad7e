#include "host/scenario/scenario_validation.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "dut_fw/sensor_node.h"
#include "dut_fw/tactile_processor.h"
#include "fixtures/objects/object_fixtures.h"
#include "host/plant/gripper_frame.h"
#include "host/plant/quadrotor.h"
#include "host/plant/servo.h"
#include "host/scenario/field_problems.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/spec_limits.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "host/trace/trace_sample.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

// NaN and infinity parse fine in text format but are never a meaningful parameter.
std::optional<std::string> NonFiniteProblem(const Message& message, const FieldDescriptor* field,
                                            int index) {
  const auto* reflection = message.GetReflection();
  double value = 0;
  if (field->cpp_type() == FieldDescriptor::CPPTYPE_DOUBLE) {
    value = index < 0 ? reflection->GetDouble(message, field)
                      : reflection->GetRepeatedDouble(message, field, index);
  } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_FLOAT) {
    value = index < 0 ? reflection->GetFloat(message, field)
                      : reflection->GetRepeatedFloat(message, field, index);
  }
  if (std::isfinite(value)) return std::nullopt;
  return "must be a finite number";
}

// The longest run. Nothing timed past it can happen in any run, and the bound keeps counts derived
// from a time (zeroing_s at up to 1 kHz) well inside the firmware's 32-bit counters.
constexpr double kMaxRunDurationS = 86400;

// The slowest rate of anything sampled on the physics ticks (control, trace, IMU, VIO): periods
// are counted in ints of ticks or nanoseconds, and a rate of 1e-300 Hz once passed as "dividing"
// the physics rate and crashed the run on a division by zero. 100 s between samples is already
// slower than any scene needs.
constexpr double kMinTickedRateHz = 0.01;

// Flights happen around a bench, and the DUT's float build resolves a position 1 km out to
// 0.06 mm; far beyond that a double stops resolving motion at all (at 1e300 m the vehicle cannot
// move, and a run held its altitude there until the setpoint changed).
constexpr double kMaxPositionM = 1000;

void RequireNearOrigin(const proto::Vector3& position_m, const ProblemList& problems) {
  const std::pair<const char*, double> axes[] = {
      {"x", position_m.x()}, {"y", position_m.y()}, {"z", position_m.z()}};
  for (const auto& [axis, value] : axes) {
    // A non-finite one is already reported as such.
    if (std::isfinite(value) && std::abs(value) > kMaxPositionM) {
      problems.Add(axis, "must be within 1000 m of the origin");
    }
  }
}

void RequirePositive(bool has, double value, const char* field, const ProblemList& problems) {
  if (has && !(value > 0)) problems.Add(field, "must be > 0, got " + rig::NumberText(value));
}

void RequireNonNegative(bool has, double value, const char* field, const ProblemList& problems) {
  if (has && !(value >= 0)) problems.Add(field, "must be >= 0, got " + rig::NumberText(value));
}

// A finite value > 0 (strictly) or >= 0.
void RequireFiniteAtLeast(bool has, double value, bool strictly, const char* field,
                          const ProblemList& problems) {
  if (!has) return;
  const bool ok = std::isfinite(value) && (strictly ? value > 0 : value >= 0);
  if (!ok) {
    problems.Add(field,
                 std::string(strictly ? "must be finite and > 0" : "must be finite and >= 0") +
                     ", got " + rig::NumberText(value));
  }
}

void CheckVehicle(const proto::Vehicle& vehicle, const ProblemList& problems) {
  RequirePositive(vehicle.has_mass_kg(), vehicle.mass_kg(), "mass_kg", problems);
  RequirePositive(vehicle.has_arm_length_m(), vehicle.arm_length_m(), "arm_length_m", problems);
  RequirePositive(vehicle.has_max_thrust_per_rotor_n(), vehicle.max_thrust_per_rotor_n(),
                  "max_thrust_per_rotor_n", problems);
  RequireNonNegative(vehicle.has_torque_per_thrust_m(), vehicle.torque_per_thrust_m(),
                     "torque_per_thrust_m", problems);
  RequireNonNegative(vehicle.has_rotor_time_constant_s(), vehicle.rotor_time_constant_s(),
                     "rotor_time_constant_s", problems);
  RequireNonNegative(vehicle.has_linear_drag_n_s_per_m(), vehicle.linear_drag_n_s_per_m(),
                     "linear_drag_n_s_per_m", problems);
  // Finite as well: an infinitely stiff gear is the one-step stop the gear exists to avoid.
  RequireFiniteAtLeast(vehicle.has_landing_gear_stiffness_n_per_m(),
                       vehicle.landing_gear_stiffness_n_per_m(), /*strictly=*/true,
                       "landing_gear_stiffness_n_per_m", problems);
  RequireFiniteAtLeast(vehicle.has_landing_gear_damping_n_s_per_m(),
                       vehicle.landing_gear_damping_n_s_per_m(), /*strictly=*/false,
                       "landing_gear_damping_n_s_per_m", problems);
  if (vehicle.has_inertia_kg_m2()) {
    const auto& inertia = vehicle.inertia_kg_m2();
    if (!(inertia.x() > 0 && inertia.y() > 0 && inertia.z() > 0)) {
      problems.Add("inertia_kg_m2", "every principal moment must be > 0");
    }
  }
  if (vehicle.initial_position_m().z() < 0) {
    problems.Nested("initial_position_m").Add("z", "must be >= 0 (the ground is at z = 0)");
  }
  RequireNearOrigin(vehicle.initial_position_m(), problems.Nested("initial_position_m"));
}

// The adaptive integrator's error bound is relative and absolute at once; at 1 or above it no
// longer bounds anything, and 0 could never be met.
void CheckIntegratorTolerance(const proto::Models& models, const ProblemList& problems) {
  if (!models.has_integrator_tolerance()) return;
  const double tolerance = models.integrator_tolerance();
  if (!(tolerance > 0 && tolerance < 1)) {
    problems.Add("integrator_tolerance", "must be > 0 and < 1, got " + rig::NumberText(tolerance));
  }
}

// The IMU and VIO emulators sample on physics ticks: a faster rate cannot be had (at 1e300 Hz
// the VIO's period rounded to 0 ns and the run died dividing by it).
void RequireTickedRate(bool has, double rate_hz, double physics_rate_hz,
                       const ProblemList& problems) {
  if (!has) return;
  if (!(rate_hz > 0)) {
    problems.Add("rate_hz", "must be > 0, got " + rig::NumberText(rate_hz));
  } else if (rate_hz < kMinTickedRateHz || rate_hz > physics_rate_hz) {
    problems.Add("rate_hz", "must be in [0.01 Hz, physics_rate_hz (" +
                                rig::NumberText(physics_rate_hz) + " Hz)]");
  }
}

void CheckSensors(const proto::Models& models, double physics_rate_hz,
                  const ProblemList& problems) {
  const ProblemList imu = problems.Nested("imu");
  RequireTickedRate(models.imu().has_rate_hz(), models.imu().rate_hz(), physics_rate_hz, imu);
  RequireNonNegative(models.imu().has_gyro_noise_density_rad_s_sqrt_hz(),
                     models.imu().gyro_noise_density_rad_s_sqrt_hz(),
                     "gyro_noise_density_rad_s_sqrt_hz", imu);
  RequireNonNegative(models.imu().has_accel_noise_density_m_s2_sqrt_hz(),
                     models.imu().accel_noise_density_m_s2_sqrt_hz(),
                     "accel_noise_density_m_s2_sqrt_hz", imu);
  RequireNonNegative(models.imu().has_gyro_bias_sigma_rad_s(), models.imu().gyro_bias_sigma_rad_s(),
                     "gyro_bias_sigma_rad_s", imu);
  RequireNonNegative(models.imu().has_accel_bias_sigma_m_s2(), models.imu().accel_bias_sigma_m_s2(),
                     "accel_bias_sigma_m_s2", imu);
  RequirePositive(models.imu().has_accel_range_m_s2(), models.imu().accel_range_m_s2(),
                  "accel_range_m_s2", imu);
  RequirePositive(models.imu().has_gyro_range_rad_s(), models.imu().gyro_range_rad_s(),
                  "gyro_range_rad_s", imu);
  const ProblemList vio = problems.Nested("vio");
  RequireTickedRate(models.vio().has_rate_hz(), models.vio().rate_hz(), physics_rate_hz, vio);
  RequireNonNegative(models.vio().has_latency_s(), models.vio().latency_s(), "latency_s", vio);
  if (models.vio().has_latency_s() && models.vio().latency_s() > 0.2) {
    vio.Add("latency_s", "must be <= 0.2 s (the DUT keeps 256 ms of state history)");
  }
  RequireNonNegative(models.vio().has_position_noise_m(), models.vio().position_noise_m(),
                     "position_noise_m", vio);
  RequireNonNegative(models.vio().has_attitude_noise_rad(), models.vio().attitude_noise_rad(),
                     "attitude_noise_rad", vio);
  const proto::Tactile& tactile = models.tactile();
  const ProblemList hall = problems.Nested("tactile");
  if (tactile.has_node_rate_hz()) {
    const auto& rates = tactile_bus::kRateHzByCode;
    if (std::find(rates.begin() + 1, rates.end(), tactile.node_rate_hz()) == rates.end()) {
      hall.Add("node_rate_hz",
               "must be a rate the node firmware supports (1, 10, 20, 25, 50, 100, "
               "200, 250, 500 or 1000 Hz)");
    }
  }
  // The nodes are stepped on ticks, one sample per tick at most: 1 kHz nodes in a 500 Hz scene
  // sent 500 samples a second each, and the DUT counted every other one as lost on the bus.
  const double node_rate_hz =
      tactile.has_node_rate_hz() ? tactile.node_rate_hz() : kDefaultNodeRateHz;
  if ((tactile.enabled() || tactile.has_node_rate_hz()) && node_rate_hz > physics_rate_hz) {
    hall.Add("node_rate_hz", "the nodes sample on physics ticks: " + rig::NumberText(node_rate_hz) +
                                 " Hz is above physics_rate_hz (" +
                                 rig::NumberText(physics_rate_hz) + " Hz)");
  }
  if (tactile.has_reference_position_m()) {
    const proto::Vector3& p = tactile.reference_position_m();
    // On the vehicle: a chip 1 m from the body is no part of it. A non-finite one is reported as
    // such.
    if (std::isfinite(p.x() + p.y() + p.z()) &&
        Eigen::Vector3d(p.x(), p.y(), p.z()).cwiseAbs().maxCoeff() > 1.0) {
      hall.Add("reference_position_m", "must be within 1 m of the body origin on every axis");
    }
  }
  RequireNonNegative(tactile.has_zeroing_s(), tactile.zeroing_s(), "zeroing_s", hall);
  if (tactile.has_zeroing_s() && tactile.zeroing_s() > kMaxRunDurationS) {
    hall.Add("zeroing_s", "must be at most 86400 s (the longest run): the DUT would never zero");
  }
  if (tactile.has_force_average_samples() &&
      (tactile.force_average_samples() < 1 ||
       tactile.force_average_samples() > dut_fw::kMaxForceAverageSamples)) {
    hall.Add("force_average_samples", "must lie in [1, " +
                                          std::to_string(dut_fw::kMaxForceAverageSamples) +
                                          "]: the DUT keeps at most that many forces per pad");
  }
  if (tactile.has_temperature_c() &&
      !(tactile.temperature_c() > -40 && tactile.temperature_c() < 125)) {
    hall.Add("temperature_c", "must be inside the MLX90393's -40..125 C");
  }
  if (tactile.has_field_fidelity()) {
    if (auto film = ParseFilmFidelity(tactile.field_fidelity()); !film) {
      hall.Add("field_fidelity", film.error().message);
    }
  }
  CheckIntegratorTolerance(models, problems);
}

// A rate must divide the physics rate so that it lands on whole ticks.
void CheckDivides(bool has, double rate_hz, double physics_rate_hz, const char* field,
                  const ProblemList& problems) {
  if (!has) return;
  if (!(rate_hz > 0)) {
    problems.Add(field, "must be > 0");
    return;
  }
  if (rate_hz < kMinTickedRateHz) {
    problems.Add(field, "must be at least 0.01 Hz");
    return;
  }
  const double ratio = physics_rate_hz / rate_hz;
  if (ratio < 1 || std::abs(ratio - std::round(ratio)) > 1e-9) {
    problems.Add(field,
                 "must divide physics_rate_hz (" + rig::NumberText(physics_rate_hz) + " Hz)");
  }
}

void CheckSimulation(const proto::Simulation& simulation, const ProblemList& problems) {
  if (!simulation.has_duration_s()) {
    problems.AddHere("duration_s is required");
  } else if (!(simulation.duration_s() > 0) || simulation.duration_s() > kMaxRunDurationS) {
    problems.Add("duration_s", "must be in (0, 86400] s");
  }
  const double physics_rate_hz = PhysicsRateHz(simulation);
  if (!(physics_rate_hz >= 10 && physics_rate_hz <= 100000)) {
    problems.Add("physics_rate_hz", "must be in [10, 100000] Hz");
    return;
  }
  if (std::abs(1e9 / physics_rate_hz - std::round(1e9 / physics_rate_hz)) > 1e-6) {
    problems.Add("physics_rate_hz", "must give a whole number of nanoseconds per step");
  }
  CheckDivides(simulation.has_control_rate_hz(), simulation.control_rate_hz(), physics_rate_hz,
               "control_rate_hz", problems);
  CheckDivides(simulation.has_trace_rate_hz(), simulation.trace_rate_hz(), physics_rate_hz,
               "trace_rate_hz", problems);
  if (simulation.has_plant_substeps() &&
      !(simulation.plant_substeps() >= 1 && simulation.plant_substeps() <= 1000)) {
    problems.Add("plant_substeps", "must be in [1, 1000]");
  }
  if (simulation.has_can_bitrate_bps() &&
      !(simulation.can_bitrate_bps() >= 10e3 && simulation.can_bitrate_bps() <= 8e6)) {
    problems.Add("can_bitrate_bps", "must be in [10 kbit/s, 8 Mbit/s]");
  }
}

void CheckObject(const proto::GraspObject& object, const ProblemList& problems) {
  if (object.fixture().empty()) {
    problems.AddHere("fixture is required");
  } else if (auto fixture = fixtures::ObjectFixture(object.fixture()); !fixture) {
    problems.Add("fixture", fixture.error().message);
  }
  RequirePositive(object.has_stiffness_scale(), object.stiffness_scale(), "stiffness_scale",
                  problems);
  RequirePositive(object.has_mass_kg(), object.mass_kg(), "mass_kg", problems);
  RequirePositive(object.has_damage_force_n(), object.damage_force_n(), "damage_force_n", problems);
  RequirePositive(object.has_stand_height_m(), object.stand_height_m(), "stand_height_m", problems);
}

// The largest grasp force the servo can hold: by virtual work its torque is the pads' summed
// normal force times how far they move per radian, so at stall torque the six pads press
// stall_torque_nm / closing_m_per_rad together (10 N at the defaults, 1.7 N a pad).
double StallGraspForceN(const proto::Scenario& scenario) {
  const proto::Gripper& gripper = scenario.models().gripper();
  const double stall_torque_nm =
      gripper.has_stall_torque_nm() ? gripper.stall_torque_nm() : ServoParams{}.stall_torque_nm;
  return stall_torque_nm / GripperFrameParams{}.closing_m_per_rad;
}

// The grasp force comes from the pads, so a regulating grasp needs them; the servo cannot squeeze
// harder than its stall torque allows, so a larger target could never be reached.
void CheckGrasp(const proto::Scenario& scenario, const proto::Grasp& grasp,
                const ProblemList& problems) {
  if (!scenario.has_object()) problems.AddHere("commands the gripper, but the scene has no object");
  if (grasp.open()) return;
  if (!grasp.has_force_n()) problems.AddHere("force_n is required (or open: true)");
  const double max_n = StallGraspForceN(scenario);
  if (grasp.has_force_n() && !(grasp.force_n() > 0 && grasp.force_n() <= max_n)) {
    problems.Add("force_n", "must be in (0, " + rig::NumberText(max_n) +
                                "] N: at its stall torque the servo squeezes at most that over "
                                "the six pads");
  }
  if (!scenario.models().tactile().enabled()) {
    problems.AddHere("regulates the grasp force, which needs models.tactile.enabled");
  }
}

void CheckGraspController(const proto::GraspController& controller, const ProblemList& problems) {
  RequirePositive(controller.has_mass(), controller.mass(), "mass", problems);
  RequirePositive(controller.has_damping(), controller.damping(), "damping", problems);
  RequireNonNegative(controller.has_stiffness(), controller.stiffness(), "stiffness", problems);
}

void CheckGripper(const proto::Gripper& gripper, const ProblemList& problems) {
  RequirePositive(gripper.has_stall_torque_nm(), gripper.stall_torque_nm(), "stall_torque_nm",
                  problems);
  RequirePositive(gripper.has_max_rate_rad_s(), gripper.max_rate_rad_s(), "max_rate_rad_s",
                  problems);
  RequirePositive(gripper.has_servo_time_constant_s(), gripper.servo_time_constant_s(),
                  "servo_time_constant_s", problems);
}

void CheckTimeline(const proto::Scenario& scenario, const ProblemList& problems) {
  const double duration_s = scenario.simulation().duration_s();
  for (int i = 0; i < scenario.timeline_size(); ++i) {
    const auto& entry = scenario.timeline(i);
    const ProblemList here = problems.Element("timeline", i);
    if (!entry.has_at_s()) {
      here.AddHere("at_s is required");
    } else if (entry.at_s() < 0 || entry.at_s() > duration_s) {
      here.Add("at_s", "must lie inside the run [0, simulation.duration_s]");
    }
    switch (entry.action_case()) {
      case proto::TimelineEntry::kSetpoint:
        RequireNonNegative(entry.setpoint().has_transition_s(), entry.setpoint().transition_s(),
                           "transition_s", here.Nested("setpoint"));
        RequireNearOrigin(entry.setpoint().position_m(),
                          here.Nested("setpoint").Nested("position_m"));
        break;
      case proto::TimelineEntry::kDisturbance:
        if (!entry.disturbance().has_duration_s()) {
          here.Nested("disturbance").AddHere("duration_s is required");
        }
        RequirePositive(entry.disturbance().has_duration_s(), entry.disturbance().duration_s(),
                        "duration_s", here.Nested("disturbance"));
        break;
      case proto::TimelineEntry::kGrasp:
        CheckGrasp(scenario, entry.grasp(), here.Nested("grasp"));
        break;
      case proto::TimelineEntry::kPour: {
        const ProblemList pour = here.Nested("pour");
        if (!entry.pour().has_mass_kg()) pour.AddHere("mass_kg is required");
        RequirePositive(entry.pour().has_mass_kg(), entry.pour().mass_kg(), "mass_kg", pour);
        if (!entry.pour().has_duration_s()) pour.AddHere("duration_s is required");
        RequirePositive(entry.pour().has_duration_s(), entry.pour().duration_s(), "duration_s",
                        pour);
        if (!scenario.has_object()) pour.AddHere("pours into the object, but the scene has none");
        break;
      }
      case proto::TimelineEntry::kStrayField: {
        const ProblemList stray = here.Nested("stray_field");
        const proto::StrayField& field = entry.stray_field();
        if (!field.has_node() || field.node() < 1 || field.node() > 7) {
          stray.Add("node", "must be a Hall sensor node, 1..7");
        } else if (field.node() <= 6 && !scenario.models().tactile().enabled()) {
          stray.Add("node", "is a tactile pad, but models.tactile.enabled is false");
        }
        if (!field.has_duration_s()) stray.AddHere("duration_s is required");
        RequirePositive(field.has_duration_s(), field.duration_s(), "duration_s", stray);
        break;
      }
      case proto::TimelineEntry::kRemoveSupport:
        if (!scenario.has_object()) {
          here.Nested("remove_support").AddHere("the scene has no object on a stand");
        }
        break;
      case proto::TimelineEntry::kPresentObject:
        CheckObject(entry.present_object(), here.Nested("present_object"));
        if (!scenario.has_object()) {
          here.Nested("present_object")
              .AddHere("replaces the scene's object: set `object` for the first one");
        }
        break;
      case proto::TimelineEntry::ACTION_NOT_SET:
        here.AddHere(
            "needs an action: setpoint, disturbance, grasp, pour, present_object or "
            "remove_support");
        break;
    }
  }
}

bool WatchesGrasp(proto::Signal signal) {
  return (signal >= proto::GRASP_FORCE_N && signal <= proto::SERVO_ANGLE_RAD) ||
         signal == proto::OBJECT_HELD || signal == proto::SLIP_SPEED_M_S;
}

bool WatchesPads(proto::Signal signal) {
  return signal == proto::TACTILE_FORCE_N || signal == proto::TACTILE_FORCE_ERROR_N ||
         IsPadSignal(signal);
}

// The signal exists in this scene: the pads' signals need the tactile model, the grasp's an
// object, and a PAD_* signal the pad it watches.
void CheckEnvelopeSignalFits(const proto::Envelope& envelope, const proto::Scenario& scenario,
                             const ProblemList& here) {
  if (WatchesPads(envelope.signal()) && !scenario.models().tactile().enabled()) {
    here.Add("signal", "watches the tactile pads, but models.tactile.enabled is false");
  }
  if (WatchesGrasp(envelope.signal()) && !scenario.has_object()) {
    here.Add("signal", "watches the grasp, but the scene has no object");
  }
  if (IsPadSignal(envelope.signal())) {
    if (!envelope.has_pad()) {
      here.AddHere("signal " + proto::Signal_Name(envelope.signal()) +
                   " needs pad: the tactile pad it watches, 0 to " +
                   std::to_string(kTracePadCount - 1));
    } else if (envelope.pad() >= kTracePadCount) {
      here.Add("pad", "must be 0 to " + std::to_string(kTracePadCount - 1) + " (six pads), got " +
                          std::to_string(envelope.pad()));
    }
  } else if (envelope.has_pad()) {
    here.Add("pad", "only a PAD_* signal watches one pad; " +
                        proto::Signal_Name(envelope.signal()) + " does not");
  }
}

void CheckEnvelopes(const proto::Scenario& scenario, const ProblemList& problems) {
  std::set<std::string> names;
  for (int i = 0; i < scenario.envelopes_size(); ++i) {
    const auto& envelope = scenario.envelopes(i);
    const ProblemList here = problems.Element("envelopes", i);
    if (envelope.name().empty()) {
      here.AddHere("name is required");
    } else if (auto problem = NameCharacterProblem(envelope.name())) {
      here.Add("name", std::move(*problem));
    } else if (!names.insert(envelope.name()).second) {
      here.Add("name", "\"" + envelope.name() + "\" is used by an earlier envelope");
    }
    if (envelope.signal() == proto::SIGNAL_UNSPECIFIED) here.AddHere("signal is required");
    if (!envelope.has_lower() && !envelope.has_upper()) {
      here.AddHere("needs a limit: lower, upper or both");
    }
    if (envelope.has_lower() && envelope.has_upper() && envelope.lower() > envelope.upper()) {
      here.Add("lower", "must not exceed upper");
    }
    if (envelope.has_from_s() && envelope.has_until_s() && envelope.from_s() > envelope.until_s()) {
      here.Add("from_s", "must not be after until_s");
    }
    RequireNonNegative(envelope.has_from_s(), envelope.from_s(), "from_s", here);
    RequirePositive(envelope.has_mean_over_s(), envelope.mean_over_s(), "mean_over_s", here);
    CheckEnvelopeSignalFits(envelope, scenario, here);
  }
}

void RequireFraction(bool has, double value, const char* field, const ProblemList& problems) {
  if (has && !(value >= 0 && value <= 1)) {
    problems.Add(field, "must be a fraction in [0, 1], got " + rig::NumberText(value));
  }
}

// A loop paced at the physics period cannot keep its period's p99 or max below that period, and a
// late threshold of a second or more would never call a tick late in any run worth grading.
void CheckTiming(const proto::Scenario& scenario, const ProblemList& problems) {
  const proto::TimingEnvelopes& timing = scenario.timing();
  const proto::Simulation& simulation = scenario.simulation();
  const double physics_rate_hz = PhysicsRateHz(simulation);
  const double period_s = 1.0 / (physics_rate_hz > 0 ? physics_rate_hz : kDefaultPhysicsRateHz);
  if (timing.has_late_threshold_s() &&
      !(timing.late_threshold_s() > 0 && timing.late_threshold_s() < 1)) {
    problems.Add("late_threshold_s",
                 "must be in (0, 1) s, got " + rig::NumberText(timing.late_threshold_s()));
  }
  const auto at_least_period = [&](bool has, double value, const char* field) {
    if (!has) return;
    if (!(value > 0)) {
      problems.Add(field, "must be > 0, got " + rig::NumberText(value));
    } else if (value < period_s * (1 - 1e-9)) {
      problems.Add(field, "must be >= the physics period (" + rig::NumberText(period_s) +
                              " s): a loop paced at that period cannot beat it");
    }
  };
  at_least_period(timing.has_loop_period_p99_max_s(), timing.loop_period_p99_max_s(),
                  "loop_period_p99_max_s");
  at_least_period(timing.has_loop_period_max_s(), timing.loop_period_max_s(), "loop_period_max_s");
  RequirePositive(timing.has_dut_latency_p99_max_s(), timing.dut_latency_p99_max_s(),
                  "dut_latency_p99_max_s", problems);
  RequireFraction(timing.has_late_tick_fraction_max(), timing.late_tick_fraction_max(),
                  "late_tick_fraction_max", problems);
  RequireFraction(timing.has_dut_commands_missed_fraction_max(),
                  timing.dut_commands_missed_fraction_max(), "dut_commands_missed_fraction_max",
                  problems);
}

void CheckTarget(const proto::Scenario& scenario, const ProblemList& problems) {
  const proto::TargetEnvelopes& target = scenario.target();
  RequireFraction(target.has_work_p99_fraction_max(), target.work_p99_fraction_max(),
                  "work_p99_fraction_max", problems);
  RequireFraction(target.has_work_max_fraction_max(), target.work_max_fraction_max(),
                  "work_max_fraction_max", problems);
}

// The tangent-plane GNSS model and the troposphere's barometer hold in these ranges.
void CheckGeodeticOrigin(const proto::GeodeticOrigin& origin, const ProblemList& problems) {
  if (!(std::abs(origin.latitude_deg()) <= 85)) {
    problems.Add("latitude_deg", "must be within -85 .. 85");
  }
  if (!(std::abs(origin.longitude_deg()) <= 180)) {
    problems.Add("longitude_deg", "must be within -180 .. 180");
  }
  if (!(origin.altitude_m() >= -400 && origin.altitude_m() <= 8000)) {
    problems.Add("altitude_m", "must be within -400 .. 8000 m (the troposphere's barometer)");
  }
}

// With every rotor at full thrust the vehicle must at least hover, or no scenario can fly it.
void CheckCanLift(const proto::Scenario& scenario, const ProblemList& problems) {
  const proto::Vehicle& vehicle = scenario.vehicle();
  const QuadrotorParams defaults;
  const double mass_kg = vehicle.has_mass_kg() ? vehicle.mass_kg() : defaults.body.mass_kg;
  const double max_thrust_n = vehicle.has_max_thrust_per_rotor_n()
                                  ? vehicle.max_thrust_per_rotor_n()
                                  : defaults.rotors.max_thrust_n;
  const double gravity_m_s2 = scenario.environment().has_gravity_m_s2()
                                  ? scenario.environment().gravity_m_s2()
                                  : defaults.gravity_m_s2;
  if (mass_kg > 0 && 4 * max_thrust_n <= mass_kg * gravity_m_s2) {
    // The numbers behind it, since any of the three may be the mistake.
    problems.Add("max_thrust_per_rotor_n",
                 "four rotors (" + rig::NumberText(4 * max_thrust_n) +
                     " N at full thrust) cannot lift the vehicle's weight (" +
                     rig::NumberText(mass_kg * gravity_m_s2) + " N: " + rig::NumberText(mass_kg) +
                     " kg at " + rig::NumberText(gravity_m_s2) + " m/s^2)");
  }
}

}  // namespace

std::vector<FieldProblem> ValidateScenario(const proto::Scenario& scenario) {
  std::vector<FieldProblem> problems;
  const ProblemList root(problems);
  // Later checks quote strings back (an unknown fixture, a repeated envelope name) and look at the
  // entries one by one: a spec past its sizes gets only those problems.
  if (!CheckSpecSizes(scenario, root)) return problems;
  CheckEveryScalar(scenario, root, NonFiniteProblem);
  CheckEveryScalar(scenario, root, ControlCharacterProblem);
  if (scenario.name().empty()) {
    root.AddHere("name is required");
  } else if (auto problem = NameCharacterProblem(scenario.name())) {
    root.Add("name", std::move(*problem));
  }
  CheckVehicle(scenario.vehicle(), root.Nested("vehicle"));
  CheckCanLift(scenario, root.Nested("vehicle"));
  CheckSensors(scenario.models(), PhysicsRateHz(scenario.simulation()), root.Nested("models"));
  if (!scenario.has_simulation()) {
    root.AddHere("simulation is required (at least simulation { duration_s: ... })");
  } else {
    CheckSimulation(scenario.simulation(), root.Nested("simulation"));
  }
  if (scenario.has_object()) CheckObject(scenario.object(), root.Nested("object"));
  CheckGripper(scenario.models().gripper(), root.Nested("models").Nested("gripper"));
  CheckGraspController(scenario.grasp_controller(), root.Nested("grasp_controller"));
  CheckTimeline(scenario, root);
  CheckEnvelopes(scenario, root);
  CheckMeanWindows(scenario, root);
  CheckTiming(scenario, root.Nested("timing"));
  CheckTarget(scenario, root.Nested("target"));
  if (scenario.environment().has_gravity_m_s2() && !(scenario.environment().gravity_m_s2() > 0)) {
    root.Nested("environment").Add("gravity_m_s2", "must be > 0");
  }
  if (scenario.environment().has_geodetic_origin()) {
    CheckGeodeticOrigin(scenario.environment().geodetic_origin(),
                        root.Nested("environment").Nested("geodetic_origin"));
  }
  return problems;
}

}  // namespace hilrig::host
