#include "host/checks/trailing_mean.h"

#include <cmath>
#include <limits>

namespace hilrig::host {

void TrailingMean::Count(double value, bool arriving) {
  const auto step = [arriving](std::size_t& count) { arriving ? ++count : --count; };
  if (std::isnan(value)) {
    step(non_finite_.nan);
  } else if (std::isinf(value)) {
    step(value > 0 ? non_finite_.positive_infinity : non_finite_.negative_infinity);
  } else {
    finite_sum_ += arriving ? value : -value;
    ++values_summed_;
  }
}

void TrailingMean::Resum() {
  finite_sum_ = 0;
  for (const auto& [time_s, value] : samples_) {
    if (std::isfinite(value)) finite_sum_ += value;
  }
  values_summed_ += samples_.size();
  departures_since_resum_ = 0;
}

void TrailingMean::Add(double time_s, double value, double span_s) {
  samples_.emplace_back(time_s, value);
  Count(value, /*arriving=*/true);
  while (!samples_.empty() && time_s - samples_.front().first >= span_s) {
    const double leaving = samples_.front().second;
    samples_.pop_front();
    Count(leaving, /*arriving=*/false);
    if (++departures_since_resum_ >= samples_.size()) Resum();
  }
}

double TrailingMean::Mean() const {
  if (non_finite_.nan > 0 ||
      (non_finite_.positive_infinity > 0 && non_finite_.negative_infinity > 0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  if (non_finite_.positive_infinity > 0) return std::numeric_limits<double>::infinity();
  if (non_finite_.negative_infinity > 0) return -std::numeric_limits<double>::infinity();
  return finite_sum_ / static_cast<double>(samples_.size());
}

}  // namespace hilrig::host
