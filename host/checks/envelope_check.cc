#include "host/checks/envelope_check.h"

#include <algorithm>
#include <cmath>

namespace hilrig::host {

EnvelopeCheck::EnvelopeCheck(EnvelopeSpec spec)
    : spec_(std::move(spec)),
      read_signal_(SignalReaderFor(spec_.signal, spec_.pad)),
      lower_(spec_.lower.value_or(-std::numeric_limits<double>::infinity())),
      upper_(spec_.upper.value_or(std::numeric_limits<double>::infinity())),
      from_s_(spec_.from_s),
      until_s_(spec_.until_s.value_or(std::numeric_limits<double>::infinity())),
      has_mean_(spec_.mean_over_s.has_value()),
      mean_over_s_(spec_.mean_over_s.value_or(0.0)) {}

double EnvelopeCheck::Margin(double value) const {
  if (!std::isfinite(value)) return -std::numeric_limits<double>::infinity();
  // A missing bound is infinitely far. Starting from +inf and folding in each side keeps what a
  // NaN bound does (std::min keeps the first argument when the second is NaN).
  double margin = std::numeric_limits<double>::infinity();
  margin = std::min(margin, value - lower_);
  margin = std::min(margin, upper_ - value);
  return margin;
}

std::optional<double> EnvelopeCheck::CheckedValue(const TraceSample& sample,
                                                  EnvelopeProgress& progress) const {
  const double value = read_signal_(sample);
  if (!has_mean_) return value;
  // Half a microsecond of slack so that a window of whole trace periods counts as full.
  constexpr double kSlackS = 5e-7;
  progress.window.Add(sample.time_s, value, mean_over_s_ - kSlackS);
  if (sample.time_s - from_s_ < mean_over_s_ - kSlackS) return std::nullopt;
  // A window shorter than the slack holds no sample: its mean is NaN (0 / 0), a violation.
  return progress.window.Mean();
}

EnvelopeReading EnvelopeCheck::Read(const TraceSample& sample, EnvelopeProgress& progress) const {
  if (sample.time_s < from_s_ || sample.time_s > until_s_) return {};
  const std::optional<double> checked = CheckedValue(sample, progress);
  if (!checked) return {};
  return {.checked = true, .value = *checked, .margin = Margin(*checked)};
}

bool EnvelopeCheck::Observe(const TraceSample& sample, EnvelopeProgress& progress) const {
  const EnvelopeReading reading = Read(sample, progress);
  if (!reading.checked) return false;
  const double value = reading.value;
  const double margin = reading.margin;
  ++progress.samples_checked;
  if (margin < progress.worst_margin || progress.samples_checked == 1) {
    progress.worst_margin = margin;
    progress.worst_value = value;
    progress.worst_at_s = sample.time_s;
  }
  const bool violation = reading.violation();
  if (violation && !progress.violated) {
    progress.violated = true;
    progress.first_violation_at_s = sample.time_s;
  }
  return violation;
}

proto::EnvelopeResult EnvelopeCheck::Result(const EnvelopeProgress& progress) const {
  proto::EnvelopeResult result;
  result.set_name(spec_.name);
  result.set_signal(spec_.signal);
  // An envelope that saw no sample proved nothing: it meets no expectation, FAIL included.
  const bool evaluated = progress.samples_checked > 0;
  result.set_verdict(progress.violated || !evaluated ? proto::FAIL : proto::PASS);
  result.set_expected(spec_.expect == EnvelopeVerdict::kFail ? proto::FAIL : proto::PASS);
  result.set_meets_expectation(evaluated && result.verdict() == result.expected());
  result.set_not_evaluated(!evaluated);
  result.set_worst_value(progress.worst_value);
  result.set_worst_at_s(progress.worst_at_s);
  if (spec_.lower) result.set_lower(*spec_.lower);
  if (spec_.upper) result.set_upper(*spec_.upper);
  result.set_margin(progress.samples_checked == 0 ? 0.0 : progress.worst_margin);
  result.set_samples_checked(progress.samples_checked);
  if (progress.violated) result.set_first_violation_at_s(progress.first_violation_at_s);
  return result;
}

}  // namespace hilrig::host
