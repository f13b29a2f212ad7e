// How far one run's trace is from another's: the sample-by-sample error of grasp force, vertical
// load and position between a run and its reference, matched by time. A sample either trace lacks
// (a run that ended early, a signal that is not finite) is counted as missing, never as an error
// of NaN.
#pragma once

#include <cstddef>

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
// the trace times both runs share (samples are matched by time, within 1 us).
ErrorMetrics CompareTraces(const CapturedTrace& run, const CapturedTrace& reference);

}  // namespace hilrig::host
