// How a graded quantity moved between a base result and a candidate's, shared by the comparison
// of two runs and of two sweeps: a margin that shrank by more than a stated fraction of the base's
// margin is worse beyond tolerance, and only that (or a check the candidate lost) gates.
#pragma once

#include "proto/compare.pb.h"

namespace hilrig::host {

// The change from `base_margin` to `candidate_margin` (more room inside the bounds is better).
// A shrink of at most `margin_fraction` * |base_margin| is WORSE_WITHIN_TOLERANCE, more is WORSE;
// a candidate NaN against a number is WORSE, a NaN base against a number BETTER, two NaNs SAME.
// Cannot fail; O(1).
proto::Change MarginChange(double base_margin, double candidate_margin, double margin_fraction);

// WORSE or ONLY_IN_BASE: the changes that make the candidate a regression.
bool CountsAsWorse(proto::Change change);

// "same", "better", "worse (within tolerance)", "WORSE", "only in base", "only in candidate".
const char* ChangeText(proto::Change change);

}  // namespace hilrig::host
