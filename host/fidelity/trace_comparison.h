// How far one run's trace is from another's: the sample-by-sample error of grasp force, vertical
// load and position between a run and its reference, matched by time. A sample either trace lacks
// (a run that ended early, a signal that is not finite) is counted as missing, never as an error
// of NaN. The comparison is made as the run goes (TraceComparison): the reference is read a sample
// at a time, so neither trace is kept and memory does not grow with the run.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>

#include "host/trace/trace_capture.h"

namespace hilrig::host {

struct ErrorMetrics {
  std::size_t samples_compared = 0;
  // Reference samples with no finite counterpart in the run (it ended early, or a signal was not
  // finite): the errors below then cover only what could be compared.
  std::size_t samples_missing = 0;
  double grasp_force_rms_n = 0, grasp_force_max_n = 0;
  double load_rms_n = 0, load_max_n = 0;
  double position_rms_m = 0, position_max_m = 0;

  bool complete() const { return samples_missing == 0 && samples_compared > 0; }
};

// Sample-by-sample |run - reference| of grasp force, vertical load and position (Euclidean), at
// the trace times both runs share (samples are matched by time, within 1 us). Each reference
// sample is matched with the first run sample not earlier than it by more than 1 us, so one is
// settled as soon as such a run sample arrives: the run's samples come in time order.
class TraceComparison {
 public:
  // The reference's next sample in time order; nullopt past its last.
  using NextReference = std::function<std::optional<ComparedSample>()>;
  explicit TraceComparison(NextReference next_reference);

  // The run's next sample (times increasing).
  void AddRun(const ComparedSample& run);
  // After the run's last sample: the reference samples still unmatched are missing.
  ErrorMetrics Finish();

 private:
  struct Accumulator {
    double sum_squares = 0, max = 0;
    void Add(double error);
    double Rms(std::size_t count) const;
  };
  // Settles `reference` against `run` (nullptr: no run sample is left to match it).
  void Settle(const ComparedSample& reference, const ComparedSample* run);
  bool Pending();  // reads the next reference sample into pending_ when there is none

  NextReference next_reference_;
  std::optional<ComparedSample> pending_;
  bool reference_ended_ = false;
  ErrorMetrics metrics_;
  Accumulator force_, load_, position_;
};

// The comparison of two whole traces.
ErrorMetrics CompareTraces(const CapturedTrace& run, const CapturedTrace& reference);

}  // namespace hilrig::host
