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
}

}  // namespace hilrig::host
