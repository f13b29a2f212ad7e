#include "host/compare/change.h"

#include <cmath>

namespace hilrig::host {

proto::Change MarginChange(double base_margin, double candidate_margin, double margin_fraction) {
  const bool base_nan = std::isnan(base_margin);
  const bool candidate_nan = std::isnan(candidate_margin);
  if (base_nan || candidate_nan) {
    if (base_nan && candidate_nan) return proto::SAME;
    return candidate_nan ? proto::WORSE : proto::BETTER;
  }
  if (candidate_margin == base_margin) return proto::SAME;
  if (candidate_margin > base_margin) return proto::BETTER;
  const double allowed = margin_fraction * std::fabs(base_margin);
  return base_margin - candidate_margin > allowed ? proto::WORSE : proto::WORSE_WITHIN_TOLERANCE;
}

bool CountsAsWorse(proto::Change change) {
  return change == proto::WORSE || change == proto::ONLY_IN_BASE;
}

const char* ChangeText(proto::Change change) {
  switch (change) {
    case proto::SAME:
      return "same";
    case proto::BETTER:
      return "better";
    case proto::WORSE_WITHIN_TOLERANCE:
      return "worse (within tolerance)";
    case proto::WORSE:
      return "WORSE";
    case proto::ONLY_IN_BASE:
      return "only in base";
    case proto::ONLY_IN_CANDIDATE:
      return "only in candidate";
    default:
      return "unknown";
  }
}

}  // namespace hilrig::host
