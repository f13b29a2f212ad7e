// A validated scenario spec resolved into the plain parameter structs the runner and the models
// take, with every default filled in. The spec (protobuf, optional fields) stays at the edge; the
// runner only sees this.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/plant/quadrotor.h"
#include "host/scenario/reference_trajectory.h"
#include "host/sensors/earth_field.h"
#include "host/sensors/imu_emulator.h"
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

// The seven Hall sensor nodes and the DUT's tactile front end, resolved from models.tactile.
struct HallSensorConfig {
  bool tactile_enabled = false;  // nodes 1..6; the reference node 7 is always there
  std::string field_fidelity;
  std::array<TactileSensorParams, kTactileSensorCount> tactile;
  TactileSensorParams reference;
  double node_rate_hz = 50;
  double temperature_c = 25;
  bool compensation = true;
  double zeroing_s = 1;
  std::string calibration_file;  // resolved against the spec's folder; empty: calibrate at start
  std::optional<proto::Calibration> calibration;  // filled by LoadTactileCalibration
};

struct ScenarioConfig {
  std::string name;
  std::uint64_t seed = 1;
  double duration_s = 0;
  std::int64_t physics_step_ns = 1'000'000;
  int control_every_ticks = 1;
  int trace_every_ticks = 10;
  double can_bitrate_bps = 1e6;

  QuadrotorParams vehicle;
  ImuParams imu;
  VioParams vio;
  HallSensorConfig hall_sensors;
  EarthField earth_field;

  ReferenceSample initial_reference;  // also where the vehicle starts, at rest
  std::vector<SetpointCommand> setpoints;
  std::vector<DisturbanceCommand> disturbances;
  std::vector<proto::Envelope> envelopes;
  proto::Models models;  // the fidelity choices, for the report
};

// `seed_override` replaces the spec's seed (the --seed flag); relative file names in the spec are
// taken from `spec_directory`.
ScenarioConfig ResolveScenario(const proto::Scenario& spec,
                               std::optional<std::uint64_t> seed_override,
                               const std::string& spec_directory = "");

// The DUT's tactile calibration, as the firmware would be flashed with it: read from the spec's
// calibration file, or found by running the calibration jigs on the scene's own sensor models.
// Does nothing when the tactile nodes are off.
rig::Result<void> LoadTactileCalibration(ScenarioConfig& config);

}  // namespace hilrig::host
