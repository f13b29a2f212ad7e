// One magnetic tactile sensor node's forward model, end to end: the contact force on the pad
// deforms the silicone (silicone_model.h), which moves the film; the film's field at the Hall chip
// (a FilmFieldModel, owned by the caller and shared by all nodes) adds to Earth's field rotated
// into the sensor frame by the vehicle attitude and the node's mounting; the MLX90393 model
// (mlx90393_model.h) turns the sum into the chip's result words. Nothing here looks at how the
// DUT decodes the words: it is physics in the forward direction only.
//
// The reference node (7) is the same chain with no film and no silicone (`film_present` false):
// it reads Earth's field through the same chip model, so tactile and reference readings share
// one Earth-field rotation (earth_field.h) and one quantizer.
//
// Frames: the sensor frame is the chip frame of film_field.h (film at -z, 10 mm below the chip);
// mounting_body_from_sensor is R_BS; the vehicle attitude is R_WB (world z up).
#ifndef HILRIG_HOST_SENSORS_TACTILE_TACTILE_SENSOR_H_
#define HILRIG_HOST_SENSORS_TACTILE_TACTILE_SENSOR_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

#include "host/sensors/tactile/film_field.h"
#include "host/sensors/tactile/mlx90393_model.h"
#include "host/sensors/tactile/silicone_model.h"

namespace hilrig::host {

struct TactileSensorParams {
  SiliconeParams silicone;
  Mlx90393Params chip;
  Eigen::Quaterniond mounting_body_from_sensor = Eigen::Quaterniond::Identity();  // R_BS
  Eigen::Vector3d position_body_m = Eigen::Vector3d::Zero();  // chip position in the body frame
  std::uint8_t node_id = 1;                                   // 1..6 tactile, 7 reference
  bool earth_field_enabled = true;
  bool film_present = true;  // false: an unloaded magnetometer (the reference node)
};

struct TactileSensorState {
  SiliconeState silicone;
  Mlx90393State chip;
};

struct TactileReading {
  std::uint8_t node_id = 0;
  std::array<std::uint16_t, 3> code{};  // MLX90393 result words x, y, z
  bool saturated = false;
  FilmPose film_pose;                                              // chip frame
  Eigen::Vector3d film_field_t = Eigen::Vector3d::Zero();          // film only, sensor frame
  Eigen::Vector3d earth_field_sensor_t = Eigen::Vector3d::Zero();  // Earth only, sensor frame
  Eigen::Vector3d stray_field_sensor_t = Eigen::Vector3d::Zero();  // anything else, sensor frame
  Eigen::Vector3d field_sensor_t = Eigen::Vector3d::Zero();        // true total at the chip
};

// Initial state: film at rest, the chip's noise stream seeded from the scenario seed and the
// node (node id n uses TactileStreamId(n - 1), so nodes 1..7 take streams 10..16).
TactileSensorState InitialTactileSensorState(const TactileSensorParams& params,
                                             std::uint64_t scenario_seed);

// The parameter-only parts of the chain for a node sampling every dt_s, built once per node (and
// again only if its rate changes): see SiliconeStep and Mlx90393Constants.
struct TactileSensorConstants {
  SiliconeStep silicone;
  Mlx90393Constants chip;
  Eigen::Matrix3d sensor_from_body = Eigen::Matrix3d::Identity();  // SensorFromBody(mounting)
};
TactileSensorConstants MakeTactileSensorConstants(const TactileSensorParams& params, double dt_s);

// An exact memo of one node's last silicone step and film field. The step and the field are pure
// functions of the silicone state and the pad force for fixed parameters and film, so when both
// are bit for bit those of the last sample (a pad at rest: zero force, the film already at its
// rest pose) the last answer is the answer, and the Newton solve and the field are skipped. A
// memo serves one (params, constants, film); Reset it when any of them changes.
class PadFieldMemo {
 public:
  void Reset() { valid_ = false; }

 private:
  friend TactileReading SampleTactileSensor(const TactileSensorParams&,
                                            const TactileSensorConstants&, TactileSensorState&,
                                            const FilmFieldModel&, const Eigen::Vector3d&,
                                            const Eigen::Vector3d&, double, const Eigen::Vector3d&,
                                            PadFieldMemo*);
  bool valid_ = false;
  Eigen::Vector3d force_pad_n_ = Eigen::Vector3d::Zero();
  SiliconeState silicone_before_;
  SiliconeState silicone_after_;
  FilmPose film_pose_;
  Eigen::Vector3d film_field_t_ = Eigen::Vector3d::Zero();
};

// Advances the silicone by constants.silicone.dt_s under force_pad_n (pad frame, see
// silicone_model.h) and samples the chip at the new film pose. With film_present false the force
// and film model are ignored. `stray_field_sensor_t` is any other field at the chip (a tool or
// magnet nearby), chip frame. `constants` must come from MakeTactileSensorConstants(params, ...).
// With a `memo` (see PadFieldMemo) the reading is the same, bit for bit. `earth_field_body_t` is
// EarthFieldInBodyFrame(vehicle attitude, Earth's field), which every sensor on the vehicle
// shares.
TactileReading SampleTactileSensor(const TactileSensorParams& params,
                                   const TactileSensorConstants& constants,
                                   TactileSensorState& state, const FilmFieldModel& film,
                                   const Eigen::Vector3d& force_pad_n,
                                   const Eigen::Vector3d& earth_field_body_t, double temperature_c,
                                   const Eigen::Vector3d& stray_field_sensor_t,
                                   PadFieldMemo* memo = nullptr);

// The same for a one-off sample after dt_s.
TactileReading SampleTactileSensor(
    const TactileSensorParams& params, TactileSensorState& state, const FilmFieldModel& film,
    const Eigen::Vector3d& force_pad_n, const Eigen::Quaterniond& vehicle_attitude_world_body,
    const Eigen::Vector3d& earth_field_world_t, double temperature_c, double dt_s,
    const Eigen::Vector3d& stray_field_sensor_t = Eigen::Vector3d::Zero());

}  // namespace hilrig::host

#endif  // HILRIG_HOST_SENSORS_TACTILE_TACTILE_SENSOR_H_
