#include "host/trace/trace_capture.h"

namespace hilrig::host {

ComparedSample ComparedColumnsOf(const TraceSample& sample) {
  return {sample.time_s, sample.position_m, sample.grasp_force_n, sample.load_n};
}

void CapturedTrace::Add(const TraceSample& sample) {
  AddCompared(sample.time_s, sample.position_m, sample.grasp_force_n, sample.load_n);
}

void CapturedTrace::AddCompared(double time, const Eigen::Vector3d& position, double grasp_force,
                                double load) {
  time_s.push_back(time);
  position_m.push_back(position);
  grasp_force_n.push_back(grasp_force);
  load_n.push_back(load);
}

void PlottedTrace::Add(const TraceSample& sample) {
  const double time = sample.time_s;
  grasp_force_n.Add(time, sample.grasp_force_n);
  grasp_force_estimate_n.Add(time, sample.grasp_force_estimate_n);
  grasp_force_setpoint_n.Add(time, sample.grasp_force_setpoint_n);
  load_n.Add(time, sample.load_n);
  load_estimate_n.Add(time, sample.load_estimate_n);
  altitude_error_m.Add(time, SignalValue(sample, proto::ALTITUDE_ERROR_M));
  horizontal_error_m.Add(time, SignalValue(sample, proto::HORIZONTAL_ERROR_M));
  for (int axis = 0; axis < 3; ++axis) {
    position_m[axis].Add(time, sample.position_m[axis]);
    reference_m[axis].Add(time, sample.reference_m[axis]);
  }
  for (std::size_t pad = 0; pad < kTracePadCount; ++pad) {
    pad_force_n[pad].Add(time, sample.pad_force_n[pad]);
    pad_force_estimate_n[pad].Add(time, sample.pad_force_estimate_n[pad]);
  }
  path.Add(sample.position_m, sample.reference_m);
}

void DecimatedPath::Add(const Eigen::Vector3d& position_m, const Eigen::Vector3d& reference_m) {
  const Point point{position_m.x(), position_m.y(), reference_m.x(), reference_m.y()};
  if (added_++ % stride_ != 0) {
    last_ = point;
    return;
  }
  if (kept_.size() == kMaxPoints) {
    // Keep the samples at multiples of the doubled stride: every other one kept so far.
    for (std::size_t i = 0; 2 * i < kept_.size(); ++i) kept_[i] = kept_[2 * i];
    kept_.resize(kMaxPoints / 2);
    stride_ *= 2;
    if ((added_ - 1) % stride_ != 0) {
      last_ = point;
      return;
    }
  }
  if (kept_.capacity() < kMaxPoints) kept_.reserve(kMaxPoints);
  kept_.push_back(point);
  last_.reset();
}

std::vector<DecimatedPath::Point> DecimatedPath::ToPoints() const {
  std::vector<Point> points = kept_;
  if (last_) points.push_back(*last_);
  return points;
}

}  // namespace hilrig::host
