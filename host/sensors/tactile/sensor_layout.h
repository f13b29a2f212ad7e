// Where the seven Hall sensors sit on the vehicle: six tactile pads on the inner wall of the
// central frame and the unloaded reference magnetometer on the body. The layout gives each
// sensor's mounting (R_BS) and position, and the two quantities the DUT needs from the geometry:
// the contact normal n_i of each pad in the body frame (the grasp force is sum_i |f_i . n_i|)
// and R_{Si<-Sref}, which carries the reference reading of Earth's field into sensor i for the
// geomagnetic compensation B_i - R_{Si<-Sref} B_ref.
//
// Geometry: the pads are evenly spaced on a ring of radius 50 mm in the body x-y plane, at
// azimuths 30, 90, ..., 330 deg (so opposite pads face each other across the grasp, none on the
// nose axis). Sensor frame of pad i at azimuth a:
//   z_S = ( cos a,  sin a, 0)  radially outward, because film_field.h puts the film at -z of the
//                              chip: the chip is in the wall, the film faces the frame centre;
//   y_S = ( 0,      0,     1)  body up;
//   x_S = (-sin a,  cos a, 0)  tangential, counter-clockwise seen from above (x = y cross z).
// So pad shear is x (along the wall) and y (vertical: a held payload's weight), and the contact
// normal, the pad's surface normal pointing into the grasp space, is n_i = -z_S, towards the
// centre. The reference sensor sits on a mast above the body, axes aligned with the body.
#ifndef HILRIG_HOST_SENSORS_TACTILE_SENSOR_LAYOUT_H_
#define HILRIG_HOST_SENSORS_TACTILE_SENSOR_LAYOUT_H_

#include <Eigen/Core>
#include <array>
#include <numbers>

#include "host/sensors/tactile/tactile_sensor.h"

namespace hilrig::host {

inline constexpr int kTactileSensorCount = 6;
inline constexpr std::uint8_t kReferenceSensorNodeId = 7;

struct TactileRingGeometry {
  double radius_m = 0.050;                            // chip to frame centre
  double height_m = 0.0;                              // ring plane above the body origin
  double first_azimuth_rad = std::numbers::pi / 6.0;  // 30 deg; the rest follow every 60 deg
};

// Six tactile sensors (node ids 1..6, counter-clockwise from first_azimuth), each a copy of
// `base` with its own mounting, position and node id.
std::array<TactileSensorParams, kTactileSensorCount> DefaultTactileLayout(
    const TactileSensorParams& base = {}, const TactileRingGeometry& ring = {});

// How high above the body origin the reference magnetometer sits by default: on a mast, where the
// six films' field (film_cross_talk.h) stays under about 0.5 uT however far the frame closes.
// Nearer the ring it is not Earth's field alone: 30 uT (frame open) to 200 uT (closed on a
// bottle) at 20 mm, 12-15 uT at 50 mm, under 2.4 uT from 100 mm.
inline constexpr double kReferenceHeightM = 0.150;

// The reference magnetometer: node 7, no film, kReferenceHeightM above the body origin,
// body-aligned.
TactileSensorParams DefaultReferenceSensor();

// Contact normal of a pad in the body frame: the pad's surface normal, pointing away from the
// silicone into the grasp space (towards the frame centre in the default layout).
Eigen::Vector3d ContactNormalBody(const TactileSensorParams& sensor);

// R_{Si<-Sref} = R_BSi^T R_BSref: maps a vector from the reference sensor's frame to sensor i's.
Eigen::Matrix3d RotationSensorFromReference(const TactileSensorParams& sensor,
                                            const TactileSensorParams& reference);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_SENSORS_TACTILE_SENSOR_LAYOUT_H_
