// Envelope checks: a signal of the trace must stay inside [lower, upper] over a time window. The
// same code grades a run online (sample by sample, so a run can abort at the first violation) and
// offline (over a recorded trace). A sample that is NaN or infinite counts as a violation: a check
// never passes on numbers that are not there. With `mean_over_s` the check reads the mean of the
// signal over that trailing window (a NaN anywhere in the window makes the mean NaN).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>

#include "host/checks/envelope_spec.h"
#include "host/checks/trailing_mean.h"
#include "host/trace/trace_sample.h"
#include "proto/report.pb.h"

namespace hilrig::host {

struct EnvelopeProgress {
  std::uint64_t samples_checked = 0;
  double worst_margin = std::numeric_limits<double>::infinity();
  double worst_value = std::numeric_limits<double>::quiet_NaN();
  double worst_at_s = 0;
  bool violated = false;
  double first_violation_at_s = 0;
  TrailingMean window;  // for mean_over_s
};

// What an envelope reads at one trace sample, before it is folded into the verdict.
struct EnvelopeReading {
  // The sample counts: it is inside the time window, and with mean_over_s the mean's window is
  // full. value and margin are NaN otherwise.
  bool checked = false;
  double value = std::numeric_limits<double>::quiet_NaN();   // the signal, or its trailing mean
  double margin = std::numeric_limits<double>::quiet_NaN();  // to the nearer bound, > 0 inside
  // A checked sample outside the bounds (a non-finite value included).
  bool violation() const { return checked && margin < 0; }
};

class EnvelopeCheck {
 public:
  explicit EnvelopeCheck(EnvelopeSpec spec);

  // Reads one trace sample (the trailing mean's window takes it in): what Observe folds in, for
  // those that show an envelope sample by sample (the run's log). Samples come in time order.
  EnvelopeReading Read(const TraceSample& sample, EnvelopeProgress& progress) const;

  // Folds one trace sample into `progress`; returns true when this sample is a violation.
  bool Observe(const TraceSample& sample, EnvelopeProgress& progress) const;

  // The verdict so far. A check that saw no sample in its window fails: it proved nothing.
  proto::EnvelopeResult Result(const EnvelopeProgress& progress) const;

  const EnvelopeSpec& spec() const { return spec_; }

 private:
  // Distance inside the bounds: positive inside, negative outside, -inf for a non-finite value.
  double Margin(double value) const;
  // The value to check at this sample, or nothing while the mean's window is still filling.
  std::optional<double> CheckedValue(const TraceSample& sample, EnvelopeProgress& progress) const;

  // The spec resolved once, so that a sample costs no dispatch on the signal and no test for a
  // missing bound (an infinite one).
  EnvelopeSpec spec_;
  SignalReader read_signal_;
  double lower_;
  double upper_;
  double from_s_;
  double until_s_;
  bool has_mean_;
  double mean_over_s_;
};

}  // namespace hilrig::host
