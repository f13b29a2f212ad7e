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
    default:
      return std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace hilrig::host
