// The cases of two sweeps side by side (their runs.csv, runs_csv.h): which passed in the base and
// not in the candidate, which the reverse, and which only one sweep has. Cases are matched by
// scenario, seed and axis values, never by row order or case number, which a seed list or an axis
// changed between the sweeps shifts; the axes are matched by path, so their order may differ. Two
// sweeps over different axes have no case in common, and the comparison says so instead of
// listing every case as only on one side. The changes are information for the reader: the pass
// rates, margins and criteria (sweep_comparison.h) decide whether the candidate is worse.
#pragma once

#include "host/compare/runs_csv.h"
#include "proto/compare.pb.h"

namespace hilrig::host {

// The cases of each kind listed by name; the rest are counted.
inline constexpr int kMaxListedCases = 20;

// Compares the cases of `candidate` against those of `base`. A case is matched once: two cases
// with the same scenario, seed and values (a list axis that repeats a value) pair up in their
// files' order. Cannot fail; O(n log n) in the cases.
proto::CaseChanges CompareCases(const SweepCaseRows& base, const SweepCaseRows& candidate);

}  // namespace hilrig::host
