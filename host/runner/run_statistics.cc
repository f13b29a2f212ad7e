#include "host/runner/run_statistics.h"

#include <algorithm>
#include <cmath>

namespace hilrig::host {

void RunStatistics::Accumulator::Add(double value) {
  ++count;
  sum_squares += value * value;
  // A NaN sample must show in the maximum rather than vanish in std::max.
  max = std::isnan(value) ? value : std::max(max, value);
}

double RunStatistics::Accumulator::Rms() const {
  return std::sqrt(sum_squares / std::max<double>(1, static_cast<double>(count)));
}

void RunStatistics::Add(const TraceSample& sample) {
  position_error_m_.Add(SignalValue(sample, proto::POSITION_ERROR_M));
  horizontal_error_m_.Add(SignalValue(sample, proto::HORIZONTAL_ERROR_M));
  altitude_error_m_.Add(SignalValue(sample, proto::ALTITUDE_ERROR_M));
  tilt_deg_.Add(sample.tilt_deg);
  if (!grasp_scene_) return;
  grasp_estimate_error_n_.Add(SignalValue(sample, proto::GRASP_FORCE_ERROR_N));
  load_estimate_error_n_.Add(SignalValue(sample, proto::LOAD_ESTIMATE_ERROR_N));
  grasp_force_peak_n_ = std::max(grasp_force_peak_n_, sample.grasp_force_n);
  if (sample.grasp_force_setpoint_n > 0 && sample.grasp_settled_s >= kGraspSettleS) {
    grasp_tracking_error_n_.Add(std::abs(sample.grasp_force_n - sample.grasp_force_setpoint_n));
  }
}

void RunStatistics::AppendMetrics(proto::Report& report) const {
  const auto append = [&](const std::string& name, const Accumulator& accumulator,
                          const std::string& unit) {
    AddMetric(report, name + "_rms", accumulator.Rms(), unit);
    AddMetric(report, name + "_max", accumulator.max, unit);
  };
  append("position_error", position_error_m_, "m");
  append("horizontal_error", horizontal_error_m_, "m");
  append("altitude_error", altitude_error_m_, "m");
  append("tilt", tilt_deg_, "deg");
  if (!grasp_scene_ || grasp_estimate_error_n_.count == 0) return;
  append("grasp_force_tracking_error", grasp_tracking_error_n_, "N");
  append("grasp_force_estimate_error", grasp_estimate_error_n_, "N");
  append("load_estimate_error", load_estimate_error_n_, "N");
  AddMetric(report, "grasp_force_peak", grasp_force_peak_n_, "N");
}

void AddMetric(proto::Report& report, const std::string& name, double value,
               const std::string& unit) {
  proto::Metric* metric = report.add_metrics();
  metric->set_name(name);
  metric->set_value(value);
  metric->set_unit(unit);
}

}  // namespace hilrig::host
