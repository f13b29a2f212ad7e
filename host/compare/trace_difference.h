// Two runs' trace.csv files read side by side, row by row and signal by signal: each signal's
// largest difference and the first time the two differ beyond a tolerance, which says where a
// candidate's behaviour parted from the base's. The files are streamed, so an hour-long trace
// needs no more memory than a short one.
#pragma once

#include <istream>

#include "proto/compare.pb.h"

namespace hilrig::host {

// Compares the traces on their shared columns (by header name), over the rows both have while
// their times agree. Samples a and b differ beyond tolerance when |a - b| > trace_abs +
// trace_rel * max(|a|, |b|); two NaNs are equal, a NaN against a number differs by +inf. Cannot
// fail: a missing header, a row that is not numbers or has the wrong width ends the comparison
// there with `problem` saying where (`compared` is false when not one row could be read). O(rows x
// columns) time, O(columns) memory.
proto::TraceComparison CompareTraces(std::istream& base, std::istream& candidate,
                                     const proto::CompareTolerances& tolerances);

}  // namespace hilrig::host
