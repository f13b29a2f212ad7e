#include "host/sensors/tactile/tactile_sensor.h"

#include "host/sensors/earth_field.h"
#include "host/sensors/random_stream.h"
#include "rig/check.h"

namespace hilrig::host {

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
          .chip = MakeMlx90393Constants(params.chip)};
}

TactileReading SampleTactileSensor(const TactileSensorParams& params,
                                   const TactileSensorConstants& constants,
                                   TactileSensorState& state, const FilmFieldModel& film,
                                   const Eigen::Vector3d& force_pad_n,
                                   const Eigen::Quaterniond& vehicle_attitude_world_body,
                                   const Eigen::Vector3d& earth_field_world_t, double temperature_c,
                                   const Eigen::Vector3d& stray_field_sensor_t) {
  TactileReading reading;
  reading.node_id = params.node_id;

  if (params.film_present) {
    state.silicone = StepSilicone(constants.silicone, state.silicone, force_pad_n);
    reading.film_pose = FilmPoseFor(params.silicone, state.silicone);
    reading.film_field_t = film.FieldAtChip(reading.film_pose);
  }
  if (params.earth_field_enabled) {
    reading.earth_field_sensor_t = EarthFieldInSensorFrame(
        vehicle_attitude_world_body, params.mounting_body_from_sensor, earth_field_world_t);
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
  return SampleTactileSensor(params, MakeTactileSensorConstants(params, dt_s), state, film,
                             force_pad_n, vehicle_attitude_world_body, earth_field_world_t,
                             temperature_c, stray_field_sensor_t);
}

}  // namespace hilrig::host
