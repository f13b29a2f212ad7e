// Earth's magnetic field and its rotation into a sensor's frame. World frame for the field: x east,
// y north, z up (ENU), matching the rig's world z up. The default is ~48 uT with 60 degrees
// inclination (24 uT north, 41.6 uT down), mid-latitude Europe; the design's range is 25-65 uT.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hilrig::host {

struct EarthField {
  Eigen::Vector3d field_world_t = {0.0, 2.4e-5, -4.16e-5};
};

// R_SB R_WB^T B_world = (R_WB R_BS)^T B_world, in two steps: the attitude's part, which every
// sensor on the vehicle shares (so a tick rotates the field once for all its nodes), then the
// mounting's, a fixed matrix per sensor. The one convention of this rotation: the Hall sensor
// nodes apply its two parts below, so the DUT's geomagnetic compensation is tested against it.
Eigen::Vector3d EarthFieldInSensorFrame(const Eigen::Quaterniond& orientation_world_body,
                                        const Eigen::Quaterniond& mounting_body_sensor,
                                        const Eigen::Vector3d& field_world_t);
// R_WB^T B_world. Cannot fail; O(1).
Eigen::Vector3d EarthFieldInBodyFrame(const Eigen::Quaterniond& orientation_world_body,
                                      const Eigen::Vector3d& field_world_t);
// R_SB = R_BS^T, to be made once per sensor: R_SB times EarthFieldInBodyFrame is
// EarthFieldInSensorFrame, bit for bit.
Eigen::Matrix3d SensorFromBody(const Eigen::Quaterniond& mounting_body_sensor);

}  // namespace hilrig::host
