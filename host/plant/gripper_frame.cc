#include "host/plant/gripper_frame.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rig/check.h"

namespace hilrig::host {
namespace {

rig::Result<void> FieldError(const char* field, const char* problem) {
  return rig::MakeError(std::string("gripper frame: ") + field + ": " + problem);
}

}  // namespace

rig::Result<void> ValidateGripperFrame(const GripperFrameParams& params) {
  if (!std::isfinite(params.open_radius_m) || params.open_radius_m <= 0) {
    return FieldError("open_radius_m", "must be finite and > 0");
  }
  if (!std::isfinite(params.closing_m_per_rad) || params.closing_m_per_rad <= 0) {
    return FieldError("closing_m_per_rad", "must be finite and > 0");
  }
  if (!std::isfinite(params.film_standoff_m) || params.film_standoff_m < 0) {
    return FieldError("film_standoff_m", "must be finite and >= 0");
  }
  if (!std::isfinite(params.height_m)) return FieldError("height_m", "must be finite");
  if (!std::isfinite(params.first_azimuth_rad)) {
    return FieldError("first_azimuth_rad", "must be finite");
  }
  return {};
}

double PadSurfaceRadius(const GripperFrameParams& params, double angle_rad) {
  if (std::isnan(angle_rad)) return params.open_radius_m;
  return std::max(0.0, params.open_radius_m - params.closing_m_per_rad * angle_rad);
}

Eigen::Vector3d PadOutwardBody(const GripperFrameParams& params, int pad) {
  HILRIG_CHECK(pad >= 0 && pad < kGripperPadCount, "pad index out of range");
  const double azimuth =
      params.first_azimuth_rad + pad * (2.0 * std::numbers::pi / kGripperPadCount);
  return {std::cos(azimuth), std::sin(azimuth), 0.0};
}

Eigen::Vector3d PadSurfaceBody(const GripperFrameParams& params, int pad, double angle_rad) {
  return PadSurfaceRadius(params, angle_rad) * PadOutwardBody(params, pad) +
         Eigen::Vector3d(0.0, 0.0, params.height_m);
}

Eigen::Vector3d ChipPositionBody(const GripperFrameParams& params, int pad, double angle_rad) {
  return PadSurfaceBody(params, pad, angle_rad) +
         params.film_standoff_m * PadOutwardBody(params, pad);
}

double AngleForPadRadius(const GripperFrameParams& params, double radius_m) {
  if (!std::isfinite(radius_m) || !(params.closing_m_per_rad > 0)) return 0.0;
  return (params.open_radius_m - radius_m) / params.closing_m_per_rad;
}

}  // namespace hilrig::host
