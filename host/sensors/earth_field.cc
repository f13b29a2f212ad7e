#include "host/sensors/earth_field.h"

namespace hilrig::host {

Eigen::Vector3d EarthFieldInSensorFrame(const Eigen::Quaterniond& orientation_world_body,
                                        const Eigen::Quaterniond& mounting_body_sensor,
                                        const Eigen::Vector3d& field_world_t) {
  return SensorFromBody(mounting_body_sensor) *
         EarthFieldInBodyFrame(orientation_world_body, field_world_t);
}

Eigen::Vector3d EarthFieldInBodyFrame(const Eigen::Quaterniond& orientation_world_body,
                                      const Eigen::Vector3d& field_world_t) {
  return orientation_world_body.conjugate() * field_world_t;
}

Eigen::Matrix3d SensorFromBody(const Eigen::Quaterniond& mounting_body_sensor) {
  return mounting_body_sensor.conjugate().toRotationMatrix();
}

}  // namespace hilrig::host
