// The lines `hilrig compare` prints: a row per check or envelope with its change, the traces'
// largest differences and where they part, the sweeps' cases whose verdict changed, and the
// verdict with its reasons.
#pragma once

#include <string>
#include <vector>

#include "proto/compare.pb.h"

namespace hilrig::host {

// At most this many differing signals are listed; the rest are counted.
inline constexpr int kMaxListedSignals = 12;

std::vector<std::string> RunComparisonLines(const proto::RunComparison& comparison);
std::vector<std::string> SweepComparisonLines(const proto::SweepComparison& comparison);
// A line for the scenes each side has alone, then each scene's verdict and its run's lines.
std::vector<std::string> SuiteComparisonLines(const proto::SuiteComparison& comparison);

// "candidate is WORSE than the base (tolerances):" and its reasons, or "candidate is not worse
// than the base (tolerances)"; the pass-rate tolerances are stated for `sweeps` only.
std::vector<std::string> VerdictLines(
    bool worse, const google::protobuf::RepeatedPtrField<std::string>& reasons,
    const proto::CompareTolerances& tolerances, bool sweeps);

}  // namespace hilrig::host
