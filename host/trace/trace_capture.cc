#include "host/trace/trace_capture.h"

namespace hilrig::host {

void CapturedTrace::Add(const TraceSample& sample) {
  AddCompared(sample.time_s, sample.position_m, sample.grasp_force_n, sample.load_n);
  grasp_force_estimate_n.push_back(sample.grasp_force_estimate_n);
  grasp_force_setpoint_n.push_back(sample.grasp_force_setpoint_n);
  load_estimate_n.push_back(sample.load_estimate_n);
  altitude_error_m.push_back(SignalValue(sample, proto::ALTITUDE_ERROR_M));
  horizontal_error_m.push_back(SignalValue(sample, proto::HORIZONTAL_ERROR_M));
}

void CapturedTrace::AddCompared(double time, const Eigen::Vector3d& position, double grasp_force,
                                double load) {
  time_s.push_back(time);
  position_m.push_back(position);
  grasp_force_n.push_back(grasp_force);
  load_n.push_back(load);
}

}  // namespace hilrig::host
