#include "host/sensors/tactile/sensor_layout.h"

#include <cmath>
#include <numbers>

namespace hilrig::host {

std::array<TactileSensorParams, kTactileSensorCount> DefaultTactileLayout(
    const TactileSensorParams& base, const TactileRingGeometry& ring) {
  std::array<TactileSensorParams, kTactileSensorCount> sensors;
  for (int i = 0; i < kTactileSensorCount; ++i) {
    const double azimuth =
        ring.first_azimuth_rad + i * (2.0 * std::numbers::pi / kTactileSensorCount);
    const Eigen::Vector3d outward(std::cos(azimuth), std::sin(azimuth), 0.0);
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    Eigen::Matrix3d body_from_sensor;
    body_from_sensor.col(0) = up.cross(outward);
    body_from_sensor.col(1) = up;
    body_from_sensor.col(2) = outward;

    TactileSensorParams& sensor = sensors[i];
    sensor = base;
    sensor.mounting_body_from_sensor = Eigen::Quaterniond(body_from_sensor).normalized();
    sensor.position_body_m = ring.radius_m * outward + ring.height_m * up;
    sensor.node_id = static_cast<std::uint8_t>(i + 1);
    sensor.film_present = true;
  }
  return sensors;
}

TactileSensorParams DefaultReferenceSensor() {
  TactileSensorParams reference;
  reference.node_id = kReferenceSensorNodeId;
  reference.film_present = false;
  reference.earth_field_enabled = true;
  reference.mounting_body_from_sensor = Eigen::Quaterniond::Identity();
  reference.position_body_m = Eigen::Vector3d(0.0, 0.0, kReferenceHeightM);
  return reference;
}

Eigen::Vector3d ContactNormalBody(const TactileSensorParams& sensor) {
  // The film faces -z of the chip frame (film_field.h), so the pad's outer surface does too.
  return -(sensor.mounting_body_from_sensor * Eigen::Vector3d::UnitZ());
}

Eigen::Matrix3d RotationSensorFromReference(const TactileSensorParams& sensor,
                                            const TactileSensorParams& reference) {
  return sensor.mounting_body_from_sensor.toRotationMatrix().transpose() *
         reference.mounting_body_from_sensor.toRotationMatrix();
}

}  // namespace hilrig::host
