#include "host/sensors/tactile/tactile_sensor.h"

#include <cstring>

#include "host/sensors/earth_field.h"
#include "host/sensors/random_stream.h"
#include "rig/check.h"

namespace hilrig::host {
namespace {

// Bit for bit, so that -0.0 and +0.0 (or two NaNs) never stand for each other.
template <typename T>
bool SameBits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

}  // namespace

TactileSensorState InitialTactileSensorState(const TactileSensorParams& params,
                                             std::uint64_t scenario_seed) {
  HILRIG_CHECK(params.node_id >= 1 && params.node_id <= 7, "tactile node ids are 1..7");
  TactileSensorState state;
  state.chip.rng = RandomStream::FromSeed(scenario_seed, TactileStreamId(params.node_id - 1));
  return state;
}

TactileSensorConstants MakeTactileSensorConstants(const TactileSensorParams& params, double dt_s) {
  // Without a film the silicone is never stepped, so its parameters are not checked either.
  return {.silicone = params.film_present ? MakeSiliconeStep(params.silicone, dt_s)
                                          : SiliconeStep{.dt_s = dt_s},
          .chip = MakeMlx90393Constants(params.chip),
          .sensor_from_body = SensorFromBody(params.mounting_body_from_sensor)};
}

TactileReading SampleTactileSensor(const TactileSensorParams& params,
                                   const TactileSensorConstants& constants,
                                   TactileSensorState& state, const FilmFieldModel& film,
                                   const Eigen::Vector3d& force_pad_n,
                                   const Eigen::Vector3d& earth_field_body_t, double temperature_c,
                                   const Eigen::Vector3d& stray_field_sensor_t,
                                   PadFieldMemo* memo) {
  TactileReading reading;
  reading.node_id = params.node_id;

  if (params.film_present && memo != nullptr && memo->valid_ &&
      SameBits(force_pad_n, memo->force_pad_n_) &&
      SameBits(state.silicone, memo->silicone_before_)) {
    state.silicone = memo->silicone_after_;
    reading.film_pose = memo->film_pose_;
    reading.film_field_t = memo->film_field_t_;
  } else if (params.film_present) {
    const SiliconeState before = state.silicone;
    state.silicone = StepSilicone(constants.silicone, state.silicone, force_pad_n);
    reading.film_pose = FilmPoseFor(params.silicone, state.silicone);
    reading.film_field_t = film.FieldAtChip(reading.film_pose);
    if (memo != nullptr) {
      memo->valid_ = true;
      memo->force_pad_n_ = force_pad_n;
      memo->silicone_before_ = before;
      memo->silicone_after_ = state.silicone;
      memo->film_pose_ = reading.film_pose;
      memo->film_field_t_ = reading.film_field_t;
    }
  }
  if (params.earth_field_enabled) {
    reading.earth_field_sensor_t = constants.sensor_from_body * earth_field_body_t;
  }
  reading.stray_field_sensor_t = stray_field_sensor_t;
  reading.field_sensor_t =
      reading.film_field_t + reading.earth_field_sensor_t + reading.stray_field_sensor_t;

  const Mlx90393Sample chip = SampleMlx90393(params.chip, constants.chip, state.chip,
                                             reading.field_sensor_t, temperature_c);
  reading.code = chip.code;
  reading.saturated = chip.saturated;
  return reading;
}

TactileReading SampleTactileSensor(const TactileSensorParams& params, TactileSensorState& state,
                                   const FilmFieldModel& film, const Eigen::Vector3d& force_pad_n,
                                   const Eigen::Quaterniond& vehicle_attitude_world_body,
                                   const Eigen::Vector3d& earth_field_world_t, double temperature_c,
                                   double dt_s, const Eigen::Vector3d& stray_field_sensor_t) {
  return SampleTactileSensor(
      params, MakeTactileSensorConstants(params, dt_s), state, film, force_pad_n,
      EarthFieldInBodyFrame(vehicle_attitude_world_body, earth_field_world_t), temperature_c,
      stray_field_sensor_t);
}

}  // namespace hilrig::host
