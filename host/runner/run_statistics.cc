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
  using rig::Unit;
  const auto append = [&](const std::string& name, const Accumulator& accumulator, Unit unit) {
    AddMetric(report, {name + "_rms", accumulator.Rms(), unit});
    AddMetric(report, {name + "_max", accumulator.max, unit});
  };
  append("position_error", position_error_m_, Unit::kMetres);
  append("horizontal_error", horizontal_error_m_, Unit::kMetres);
  append("altitude_error", altitude_error_m_, Unit::kMetres);
  append("tilt", tilt_deg_, Unit::kDegrees);
  if (!grasp_scene_ || grasp_estimate_error_n_.count == 0) return;
  append("grasp_force_tracking_error", grasp_tracking_error_n_, Unit::kNewtons);
  append("grasp_force_estimate_error", grasp_estimate_error_n_, Unit::kNewtons);
  append("load_estimate_error", load_estimate_error_n_, Unit::kNewtons);
  AddMetric(report, {"grasp_force_peak", grasp_force_peak_n_, Unit::kNewtons});
}

void AddMetric(proto::Report& report, const rig::Metric& metric) {
  proto::Metric* added = report.add_metrics();
  added->set_name(metric.name);
  added->set_value(metric.value);
  added->set_unit(rig::UnitSymbol(metric.unit));
}

}  // namespace hilrig::host
