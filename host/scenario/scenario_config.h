// A validated scenario spec resolved into the plain parameter structs the runner and the models
// take, with every default filled in. The spec (protobuf, optional fields) stays at the edge; the
// runner only sees this. Two protobuf types remain in it: the enum proto::Signal, the key of a
// trace signal that the report names as well, and the DUT's calibration (proto::Calibration),
// which travels as its file format (proto/calibration.proto) from the calibration jigs and the
// calibration store to the firmware's configuration.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/checks/envelope_spec.h"
#include "host/plant/gripper_frame.h"
#include "host/plant/object_model.h"
#include "host/plant/quadrotor.h"
#include "host/plant/servo.h"
#include "host/scenario/reference_trajectory.h"
#include "host/sensors/earth_field.h"
#include "host/sensors/imu_emulator.h"
#include "host/sensors/navigation_sensors.h"
#include "host/sensors/tactile/film_field.h"
#include "host/sensors/tactile/sensor_layout.h"
#include "host/sensors/vio_emulator.h"
#include "proto/calibration.pb.h"
#include "proto/scenario.pb.h"
#include "rig/result.h"

namespace hilrig::host {

struct DisturbanceCommand {
  double at_s = 0;
  double duration_s = 0;
  Eigen::Vector3d force_world_n = Eigen::Vector3d::Zero();
};

struct StrayFieldEvent {
  double at_s = 0;
  double duration_s = 0;
  std::uint8_t node_id = 0;
  Eigen::Vector3d field_sensor_t = Eigen::Vector3d::Zero();
};

// The DUT's mean over each pad's last n decoded forces unless a scene sets
// models.tactile.force_average_samples: 3 divides the chip's noise by sqrt(3), which brings the
// held-out force error under 0.02 N on every axis, for one 50 Hz sample of mean delay
// (docs/tactile.md). A scene whose loop cannot afford the delay sets 1.
inline constexpr std::uint32_t kDefaultForceAverageSamples = 3;

// The seven Hall sensor nodes and the DUT's tactile front end, resolved from models.tactile.
struct HallSensorConfig {
  bool tactile_enabled = false;  // nodes 1..6; the reference node 7 is always there
  std::string field_fidelity;
  std::array<TactileSensorParams, kTactileSensorCount> tactile;
  TactileSensorParams reference;
  double node_rate_hz = 50;
  double temperature_c = 25;
  bool compensation = true;
  bool film_cross_talk = false;  // the films' fields at each other's chips and at the reference
  double zeroing_s = 1;
  // The DUT's mean over each pad's last n forces.
  std::uint32_t force_average_samples = kDefaultForceAverageSamples;
  std::string calibration_file;  // resolved against the spec's folder; empty: calibrate at start
  std::optional<proto::Calibration> calibration;  // filled by LoadTactileCalibration (host/setup)
  // The film's field at field_fidelity, built once (a field map takes a second or more to
  // tabulate) and shared by the calibration jigs, the run and a sweep's runs at the same level;
  // const, so sharing it cannot couple them. Empty: built by LoadTactileCalibration or the runner.
  std::shared_ptr<const FilmFieldModel> film_field;
  std::vector<StrayFieldEvent> stray_fields;  // from the timeline
};

// An object put on its stand at `at_s` (0: the scene's initial object).
struct ObjectPlacement {
  double at_s = 0;
  std::string fixture;
  ObjectParams object;
  double stand_height_m = 0;
};

struct GraspCommandEvent {
  double at_s = 0;
  bool regulate = false;  // false: open the frame
  double force_n = 0;
  std::optional<double> reference_angle_rad;  // unset: 2 mm before the current object's surface
};

struct PourEvent {
  double at_s = 0;
  double mass_kg = 0;
  double duration_s = 0;
};

// The gripper (servo, frame), the objects it meets, the grasp commands and mass flows of the
// timeline, and the DUT's grasp controller settings. `enabled` when the spec has an object.
struct GripperConfig {
  bool enabled = false;
  ServoParams servo;
  GripperFrameParams frame;
  std::vector<ObjectPlacement> objects;  // in time order; objects[0] is there from the start
  std::vector<GraspCommandEvent> grasps;
  std::vector<PourEvent> pours;
  std::vector<double> support_removals_s;  // the stand is taken away at these times
  // DUT firmware settings (unset gains: the firmware's defaults).
  std::optional<double> controller_mass;
  std::optional<double> controller_damping;
  std::optional<double> controller_stiffness;
  bool force_feedback = true;
  bool external_force_in_position_loop = true;
};

// The timing envelopes of a real-time run, resolved from the spec: each limit the run is graded
// against, unset when the spec sets none.
struct TimingLimits {
  std::optional<double> loop_period_p99_max_s;
  std::optional<double> loop_period_max_s;
  std::optional<double> late_tick_fraction_max;
  std::optional<double> dut_latency_p99_max_s;
  std::optional<double> dut_commands_missed_fraction_max;
};

// The target envelopes, resolved from the spec: fractions of the control period at the target's
// core clock, unset when the spec sets none.
struct TargetLimits {
  std::optional<double> work_p99_fraction_max;
  std::optional<double> work_max_fraction_max;
};

struct ScenarioConfig {
  std::string name;
  std::uint64_t seed = 1;
  double duration_s = 0;
  std::int64_t physics_step_ns = 1'000'000;
  int control_every_ticks = 1;
  int trace_every_ticks = 10;
  int plant_substeps = 1;
  double can_bitrate_bps = 1e6;
  // simulation.dut_fault: a non-finite DUT command stops the run (else the run goes on and fails).
  bool dut_fault_stops_run = false;

  QuadrotorParams vehicle;
  ImuParams imu;
  VioParams vio;
  HallSensorConfig hall_sensors;
  GripperConfig gripper;
  EarthField earth_field;
  // The magnetometer, barometer and GNSS, emulated for a DUT that takes them.
  NavigationSensorsConfig navigation;

  ReferenceSample initial_reference;  // also where the vehicle starts, at rest
  std::vector<SetpointCommand> setpoints;
  std::vector<DisturbanceCommand> disturbances;
  std::vector<EnvelopeSpec> envelopes;

  // Real-time runs: a tick starting later than this after its due time is late (default one
  // physics period), and the timing envelopes graded at the end.
  std::int64_t late_threshold_ns = 1'000'000;
  TimingLimits timing;
  TargetLimits target;
};

// The physics ticks of a run of config.duration_s, and the trace samples a run that completes
// them records (one every trace_every_ticks).
std::uint64_t TotalTicks(const ScenarioConfig& config);
std::uint64_t CompletedRunTraceSamples(const ScenarioConfig& config);
// The period the DUT is configured with and stepped at (control_every_ticks physics steps), and
// the target's work is held to.
double ControlPeriodS(const ScenarioConfig& config);

// `seed_override` replaces the spec's seed (the --seed flag); relative file names in the spec are
// taken from `spec_directory`.
// The spec must have passed ValidateScenario (unknown fixtures abort here).
ScenarioConfig ResolveScenario(const proto::Scenario& spec,
                               std::optional<std::uint64_t> seed_override,
                               const std::string& spec_directory = "");

// The spec's physics (tick) rate, or the default.
inline constexpr double kDefaultPhysicsRateHz = 1000;
// The design's sensor rate: every Hall node samples at it unless the spec sets node_rate_hz.
inline constexpr double kDefaultNodeRateHz = 50;
double PhysicsRateHz(const proto::Simulation& simulation);
// The spec's trace rate, or the default.
inline constexpr double kDefaultTraceRateHz = 100;
double TraceRateHz(const proto::Simulation& simulation);

}  // namespace hilrig::host
