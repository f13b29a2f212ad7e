// A validated scenario spec resolved into the plain parameter structs the runner and the models
// take, with every default filled in. The spec (protobuf, optional fields) stays at the edge; the
// runner only sees this.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/plant/quadrotor.h"
#include "host/scenario/reference_trajectory.h"
#include "host/sensors/imu_emulator.h"
#include "host/sensors/reference_magnetometer.h"
#include "host/sensors/vio_emulator.h"
#include "proto/scenario.pb.h"

namespace hilrig::host {

struct DisturbanceCommand {
  double at_s = 0;
  double duration_s = 0;
  Eigen::Vector3d force_world_n = Eigen::Vector3d::Zero();
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
  MagnetometerParams magnetometer;
  EarthField earth_field;

  ReferenceSample initial_reference;  // also where the vehicle starts, at rest
  std::vector<SetpointCommand> setpoints;
  std::vector<DisturbanceCommand> disturbances;
  std::vector<proto::Envelope> envelopes;
  proto::Models models;  // the fidelity choices, for the report
};

// `seed_override` replaces the spec's seed (the --seed flag).
ScenarioConfig ResolveScenario(const proto::Scenario& spec,
                               std::optional<std::uint64_t> seed_override);

}  // namespace hilrig::host
