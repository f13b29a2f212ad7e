// Summary statistics of a run's trace that go into the report as metrics: RMS and maximum of the
// position, horizontal and altitude errors over every trace sample and, in grasp scenes, of the
// grasp force against its setpoint once settled, of the DUT's grasp force and load estimates
// against the truth, and the peak grasp force.
#pragma once

#include <cstdint>

#include "host/trace/trace_sample.h"
#include "proto/report.pb.h"
#include "rig/metric.h"

namespace hilrig::host {

class RunStatistics {
 public:
  explicit RunStatistics(bool grasp_scene = false) : grasp_scene_(grasp_scene) {}
  void Add(const TraceSample& sample);
  void AppendMetrics(proto::Report& report) const;
  // A grasp force regulation counts as settled this long after its command changed.
  static constexpr double kGraspSettleS = 5.0;

 private:
  struct Accumulator {
    std::uint64_t count = 0;
    double sum_squares = 0;
    double max = 0;
    void Add(double value);
    double Rms() const;
  };

  Accumulator position_error_m_;
  Accumulator horizontal_error_m_;
  Accumulator altitude_error_m_;
  Accumulator tilt_deg_;
  bool grasp_scene_;
  Accumulator grasp_tracking_error_n_;  // |true - setpoint| while regulating, settled
  Accumulator grasp_estimate_error_n_;  // |estimate - true|
  Accumulator load_estimate_error_n_;   // |estimate - true|
  double grasp_force_peak_n_ = 0;
};

// Appends `metric` to the report, its unit as its symbol (rig::UnitSymbol).
void AddMetric(proto::Report& report, const rig::Metric& metric);

}  // namespace hilrig::host
