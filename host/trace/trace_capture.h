// The few trace columns a run keeps in memory, from one RunSinks::trace_sample callback, for both
// things that read a run's trace after it: the plots beside its report (host/report/run_plots.h)
// and its comparison with a reference (host/fidelity/trace_comparison.h). Columns, not whole
// trace rows, so an hour-long run stays small.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "host/trace/trace_sample.h"

namespace hilrig::host {

struct CapturedTrace {
  // What the comparison reads.
  std::vector<double> time_s;
  std::vector<Eigen::Vector3d> position_m;
  std::vector<double> grasp_force_n;
  std::vector<double> load_n;
  // What only the plots read; empty in a reference read back from the reference cache, which
  // keeps the compared columns alone.
  std::vector<double> grasp_force_estimate_n;
  std::vector<double> grasp_force_setpoint_n;
  std::vector<double> load_estimate_n;
  std::vector<double> altitude_error_m;
  std::vector<double> horizontal_error_m;

  std::size_t size() const { return time_s.size(); }
  void Add(const TraceSample& sample);
  void AddCompared(double time_s, const Eigen::Vector3d& position_m, double grasp_force_n,
                   double load_n);
};

}  // namespace hilrig::host
