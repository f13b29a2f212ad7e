// Keeps, in memory, the few trace columns a work-precision comparison needs (time, position, grasp
// force, vertical load) from a run, without files: add it to the run through
// RunSinks::trace_sample.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "host/trace/trace_sample.h"

namespace hilrig::host {

struct CapturedTrace {
  std::vector<double> time_s;
  std::vector<Eigen::Vector3d> position_m;
  std::vector<double> grasp_force_n;
  std::vector<double> load_n;

  std::size_t size() const { return time_s.size(); }
  void Add(const TraceSample& sample);
};

}  // namespace hilrig::host
