#include "host/runner/run_statistics.h"

#include <algorithm>
#include <cmath>

namespace hilrig::host {

void RunStatistics::Accumulator::Add(double value) {
  sum_squares += value * value;
  // A NaN sample must show in the maximum rather than vanish in std::max.
  max = std::isnan(value) ? value : std::max(max, value);
}

void RunStatistics::Add(const TraceSample& sample) {
  ++samples_;
  position_error_m_.Add(SignalValue(sample, proto::POSITION_ERROR_M));
  horizontal_error_m_.Add(SignalValue(sample, proto::HORIZONTAL_ERROR_M));
  altitude_error_m_.Add(SignalValue(sample, proto::ALTITUDE_ERROR_M));
  tilt_deg_.Add(sample.tilt_deg);
}

void RunStatistics::AppendMetrics(proto::Report& report) const {
  const double count = std::max<double>(1, static_cast<double>(samples_));
  const auto append = [&](const std::string& name, const Accumulator& accumulator,
                          const std::string& unit) {
    AddMetric(report, name + "_rms", std::sqrt(accumulator.sum_squares / count), unit);
    AddMetric(report, name + "_max", accumulator.max, unit);
  };
  append("position_error", position_error_m_, "m");
  append("horizontal_error", horizontal_error_m_, "m");
  append("altitude_error", altitude_error_m_, "m");
  append("tilt", tilt_deg_, "deg");
}

void AddMetric(proto::Report& report, const std::string& name, double value,
               const std::string& unit) {
  proto::Metric* metric = report.add_metrics();
  metric->set_name(name);
  metric->set_value(value);
  metric->set_unit(unit);
}

}  // namespace hilrig::host
