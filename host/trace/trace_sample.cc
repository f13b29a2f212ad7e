#include "host/trace/trace_sample.h"

#include <cmath>
#include <limits>

namespace hilrig::host {

double SignalValue(const TraceSample& sample, proto::Signal signal) {
  const Eigen::Vector3d error_m = sample.position_m - sample.reference_m;
  switch (signal) {
    case proto::POSITION_ERROR_M:
      return error_m.norm();
    case proto::HORIZONTAL_ERROR_M:
      return error_m.head<2>().norm();
    case proto::ALTITUDE_ERROR_M:
      return std::abs(error_m.z());
    case proto::ALTITUDE_M:
      return sample.position_m.z();
    case proto::TILT_DEG:
      return sample.tilt_deg;
    case proto::SPEED_M_S:
      return sample.velocity_m_s.norm();
    case proto::TACTILE_FORCE_N:
      return sample.tactile_force_max_n;
    case proto::TACTILE_FORCE_ERROR_N:
      return sample.tactile_force_error_max_n;
    case proto::GRASP_FORCE_N:
      return sample.grasp_force_n;
    case proto::GRASP_FORCE_ESTIMATE_N:
      return sample.grasp_force_estimate_n;
    case proto::GRASP_FORCE_ERROR_N:
      return std::abs(sample.grasp_force_estimate_n - sample.grasp_force_n);
    case proto::LOAD_N:
      return sample.load_n;
    case proto::LOAD_ESTIMATE_ERROR_N:
      return std::abs(sample.load_estimate_n - sample.load_n);
    case proto::OBJECT_DAMAGED:
      return sample.object_damaged ? 1.0 : 0.0;
    case proto::OBJECT_DROPPED:
      return sample.object_dropped ? 1.0 : 0.0;
    case proto::SERVO_ANGLE_RAD:
      return sample.servo_angle_rad;
    default:
      return std::numeric_limits<double>::quiet_NaN();
  }
}

bool AllSignalsFinite(const TraceSample& sample) {
  const google::protobuf::EnumDescriptor* signals = proto::Signal_descriptor();
  for (int i = 0; i < signals->value_count(); ++i) {
    const auto signal = static_cast<proto::Signal>(signals->value(i)->number());
    if (signal != proto::SIGNAL_UNSPECIFIED && !std::isfinite(SignalValue(sample, signal))) {
      return false;
    }
  }
  return true;
}

}  // namespace hilrig::host
