#include "rig/metric.h"

namespace hilrig::rig {

const char* UnitSymbol(Unit unit) {
  switch (unit) {
    case Unit::kCount:
      return "count";
    case Unit::kFraction:
      return "fraction";
    case Unit::kSeconds:
      return "s";
    case Unit::kHertz:
      return "Hz";
    case Unit::kBytes:
      return "B";
    case Unit::kCycles:
      return "cycles";
    case Unit::kMetres:
      return "m";
    case Unit::kDegrees:
      return "deg";
    case Unit::kNewtons:
      return "N";
    case Unit::kJoules:
      return "J";
    case Unit::kMetresPerSecond:
      return "m/s";
  }
  return "count";
}

}  // namespace hilrig::rig
