// The time base of the run's logs: simulated time 0 in can.log and run.mcap is 1e9 s after the
// Unix epoch (2001-09-09T01:46:40Z), so that tools that take log times for wall times show a
// plausible date (log2asc prints a header per frame at a zero seconds field) and the files stay
// byte-reproducible. One constant for both, so that their frames line up.
#pragma once

#include <cstdint>

namespace hilrig::host {

inline constexpr std::int64_t kRunLogEpochNs = 1'000'000'000LL * 1'000'000'000LL;

}  // namespace hilrig::host
