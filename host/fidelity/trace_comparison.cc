#include "host/fidelity/trace_comparison.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace hilrig::host {
namespace {

constexpr double kTimeMatchS = 1e-6;

bool Finite(const ComparedSample& sample) {
  return std::isfinite(sample.grasp_force_n) && std::isfinite(sample.load_n) &&
         sample.position_m.allFinite();
}

}  // namespace

void TraceComparison::Accumulator::Add(double error) {
  sum_squares += error * error;
  max = std::max(max, error);
}

double TraceComparison::Accumulator::Rms(std::size_t count) const {
  return count > 0 ? std::sqrt(sum_squares / static_cast<double>(count)) : 0.0;
}

TraceComparison::TraceComparison(NextReference next_reference)
    : next_reference_(std::move(next_reference)) {}

bool TraceComparison::Pending() {
  if (!pending_ && !reference_ended_) {
    pending_ = next_reference_();
    reference_ended_ = !pending_;
  }
  return pending_.has_value();
}

void TraceComparison::Settle(const ComparedSample& reference, const ComparedSample* run) {
  const bool matched = run != nullptr && std::abs(run->time_s - reference.time_s) <= kTimeMatchS;
  if (!matched || !Finite(*run) || !Finite(reference)) {
    ++metrics_.samples_missing;
    return;
  }
  ++metrics_.samples_compared;
  force_.Add(std::abs(run->grasp_force_n - reference.grasp_force_n));
  load_.Add(std::abs(run->load_n - reference.load_n));
  position_.Add((run->position_m - reference.position_m).norm());
}

void TraceComparison::AddRun(const ComparedSample& run) {
  // Every earlier run sample was more than 1 us before the pending reference sample, so this one
  // is the first that is not: the one it is matched with, or missed by.
  while (Pending() && !(run.time_s < pending_->time_s - kTimeMatchS)) {
    Settle(*pending_, &run);
    pending_.reset();
  }
}

ErrorMetrics TraceComparison::Finish() {
  while (Pending()) {
    Settle(*pending_, nullptr);
    pending_.reset();
  }
  ErrorMetrics metrics = metrics_;
  const std::size_t n = metrics.samples_compared;
  metrics.grasp_force_rms_n = force_.Rms(n);
  metrics.grasp_force_max_n = force_.max;
  metrics.load_rms_n = load_.Rms(n);
  metrics.load_max_n = load_.max;
  metrics.position_rms_m = position_.Rms(n);
  metrics.position_max_m = position_.max;
  return metrics;
}

ErrorMetrics CompareTraces(const CapturedTrace& run, const CapturedTrace& reference) {
  std::size_t next = 0;
  TraceComparison comparison([&]() -> std::optional<ComparedSample> {
    if (next == reference.size()) return std::nullopt;
    return reference.At(next++);
  });
  for (std::size_t i = 0; i < run.size(); ++i) comparison.AddRun(run.At(i));
  return comparison.Finish();
}

}  // namespace hilrig::host
