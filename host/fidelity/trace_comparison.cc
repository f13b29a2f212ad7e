#include "host/fidelity/trace_comparison.h"

#include <algorithm>
#include <cmath>

namespace hilrig::host {
namespace {

constexpr double kTimeMatchS = 1e-6;

struct Accumulator {
  double sum_squares = 0, max = 0;
  void Add(double error) {
    sum_squares += error * error;
    max = std::max(max, error);
  }
  double Rms(std::size_t count) const {
    return count > 0 ? std::sqrt(sum_squares / static_cast<double>(count)) : 0.0;
  }
};

bool FiniteAt(const CapturedTrace& trace, std::size_t i) {
  return std::isfinite(trace.grasp_force_n[i]) && std::isfinite(trace.load_n[i]) &&
         trace.position_m[i].allFinite();
}

}  // namespace

ErrorMetrics CompareTraces(const CapturedTrace& run, const CapturedTrace& reference) {
  ErrorMetrics metrics;
  Accumulator force, load, position;
  std::size_t j = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const double time_s = reference.time_s[i];
    while (j < run.size() && run.time_s[j] < time_s - kTimeMatchS) ++j;
    const bool matched = j < run.size() && std::abs(run.time_s[j] - time_s) <= kTimeMatchS;
    if (!matched || !FiniteAt(run, j) || !FiniteAt(reference, i)) {
      ++metrics.samples_missing;
      continue;
    }
    ++metrics.samples_compared;
    force.Add(std::abs(run.grasp_force_n[j] - reference.grasp_force_n[i]));
    load.Add(std::abs(run.load_n[j] - reference.load_n[i]));
    position.Add((run.position_m[j] - reference.position_m[i]).norm());
  }
  const std::size_t n = metrics.samples_compared;
  metrics.grasp_force_rms_n = force.Rms(n);
  metrics.grasp_force_max_n = force.max;
  metrics.load_rms_n = load.Rms(n);
  metrics.load_max_n = load.max;
  metrics.position_rms_m = position.Rms(n);
  metrics.position_max_m = position.max;
  return metrics;
}

}  // namespace hilrig::host
