// Summary statistics of a run's trace that go into the report as metrics: RMS and maximum of the
// position, horizontal and altitude errors over every trace sample.
#pragma once

#include <cstdint>

#include "host/trace/trace_sample.h"
#include "proto/report.pb.h"

namespace hilrig::host {

class RunStatistics {
 public:
  void Add(const TraceSample& sample);
  void AppendMetrics(proto::Report& report) const;

 private:
  struct Accumulator {
    double sum_squares = 0;
    double max = 0;
    void Add(double value);
  };

  std::uint64_t samples_ = 0;
  Accumulator position_error_m_;
  Accumulator horizontal_error_m_;
  Accumulator altitude_error_m_;
  Accumulator tilt_deg_;
};

void AddMetric(proto::Report& report, const std::string& name, double value,
               const std::string& unit);

}  // namespace hilrig::host
