#include "host/checks/envelope_check.h"

#include <algorithm>
#include <cmath>

namespace hilrig::host {

EnvelopeCheck::EnvelopeCheck(proto::Envelope spec)
    : spec_(std::move(spec)),
      from_s_(spec_.has_from_s() ? spec_.from_s() : 0.0),
      until_s_(spec_.has_until_s() ? spec_.until_s() : std::numeric_limits<double>::infinity()) {}

double EnvelopeCheck::Margin(double value) const {
  if (!std::isfinite(value)) return -std::numeric_limits<double>::infinity();
  double margin = std::numeric_limits<double>::infinity();
  if (spec_.has_lower()) margin = std::min(margin, value - spec_.lower());
  if (spec_.has_upper()) margin = std::min(margin, spec_.upper() - value);
  return margin;
}

std::optional<double> EnvelopeCheck::CheckedValue(const TraceSample& sample,
                                                  EnvelopeProgress& progress) const {
  const double value = SignalValue(sample, spec_.signal());
  if (!spec_.has_mean_over_s()) return value;
  // Half a microsecond of slack so that a window of whole trace periods counts as full.
  constexpr double kSlackS = 5e-7;
  auto& window = progress.window;
  window.emplace_back(sample.time_s, value);
  while (sample.time_s - window.front().first >= spec_.mean_over_s() - kSlackS) window.pop_front();
  if (sample.time_s - from_s_ < spec_.mean_over_s() - kSlackS) return std::nullopt;
  double sum = 0;
  for (const auto& [time_s, windowed] : window) sum += windowed;
  return sum / static_cast<double>(window.size());
}

bool EnvelopeCheck::Observe(const TraceSample& sample, EnvelopeProgress& progress) const {
  if (sample.time_s < from_s_ || sample.time_s > until_s_) return false;
  const std::optional<double> checked = CheckedValue(sample, progress);
  if (!checked) return false;
  const double value = *checked;
  const double margin = Margin(value);
  ++progress.samples_checked;
  if (margin < progress.worst_margin || progress.samples_checked == 1) {
    progress.worst_margin = margin;
    progress.worst_value = value;
    progress.worst_at_s = sample.time_s;
  }
  const bool violation = margin < 0;
  if (violation && !progress.violated) {
    progress.violated = true;
    progress.first_violation_at_s = sample.time_s;
  }
  return violation;
}

proto::EnvelopeResult EnvelopeCheck::Result(const EnvelopeProgress& progress) const {
  proto::EnvelopeResult result;
  result.set_name(spec_.name());
  result.set_signal(spec_.signal());
  const bool failed = progress.violated || progress.samples_checked == 0;
  result.set_verdict(failed ? proto::FAIL : proto::PASS);
  result.set_expected(spec_.expect());
  result.set_meets_expectation(result.verdict() == spec_.expect());
  result.set_worst_value(progress.worst_value);
  result.set_worst_at_s(progress.worst_at_s);
  if (spec_.has_lower()) result.set_lower(spec_.lower());
  if (spec_.has_upper()) result.set_upper(spec_.upper());
  result.set_margin(progress.samples_checked == 0 ? 0.0 : progress.worst_margin);
  result.set_samples_checked(progress.samples_checked);
  if (progress.violated) result.set_first_violation_at_s(progress.first_violation_at_s);
  return result;
}

}  // namespace hilrig::host
