#include "host/sensors/earth_field.h"

namespace hilrig::host {

Eigen::Vector3d EarthFieldInSensorFrame(const Eigen::Quaterniond& orientation_world_body,
                                        const Eigen::Quaterniond& mounting_body_sensor,
                                        const Eigen::Vector3d& field_world_t) {
  return (orientation_world_body * mounting_body_sensor).conjugate() * field_world_t;
}

}  // namespace hilrig::host
