// A figure a run measured, as a value with its unit, set where it is measured: a DUT's link counts
// messages, a target states its core clock in Hz and its flash in bytes, the bus its load as a
// fraction. The report writes the unit's symbol beside the value, so no reader takes a clock for a
// count.
#pragma once

#include <cstdint>
#include <string>
#include <utility>

namespace hilrig::rig {

enum class Unit : std::uint8_t {
  kCount,     // events, messages, frames, ticks
  kFraction,  // 0..1
  kSeconds,
  kHertz,
  kBytes,
  kCycles,  // a processor's cycle counter
  kMetres,
  kDegrees,
  kNewtons,
  kJoules,
  kMetresPerSecond,
};

// "count", "fraction", "s", "Hz", "B", "cycles", "m", "deg", "N", "J", "m/s". Cannot fail.
const char* UnitSymbol(Unit unit);

struct Metric {
  std::string name;  // snake_case, unique within a report
  double value = 0;
  Unit unit = Unit::kCount;
};

// A count, the commonest metric: `value` as a double.
inline Metric CountMetric(std::string name, std::uint64_t value) {
  return {std::move(name), static_cast<double>(value), Unit::kCount};
}

}  // namespace hilrig::rig
