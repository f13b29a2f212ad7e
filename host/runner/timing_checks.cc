#include "host/runner/timing_checks.h"

#include <cmath>
#include <string>

namespace hilrig::host {
namespace {

proto::TimingCheckResult Graded(const std::string& name, double value, double limit,
                                const std::string& unit, std::string note = "") {
  proto::TimingCheckResult result;
  result.set_name(name);
  result.set_evaluated(true);
  result.set_value(value);
  result.set_limit(limit);
  result.set_unit(unit);
  result.set_passed(std::isfinite(value) && value <= limit);
  result.set_note(std::move(note));
  return result;
}

proto::TimingCheckResult NotEvaluated(const std::string& name, double limit,
                                      const std::string& unit, const std::string& why) {
  proto::TimingCheckResult result;
  result.set_name(name);
  result.set_evaluated(false);
  result.set_passed(true);
  result.set_limit(limit);
  result.set_unit(unit);
  result.set_note("not evaluated (" + why + ")");
  return result;
}

// A real-time run that never measured the figure (it stopped at once) fails the check: it proved
// nothing. The value stays 0 so that no NaN reaches the report.
proto::TimingCheckResult Unmeasured(const std::string& name, double limit, const std::string& unit,
                                    const std::string& why) {
  proto::TimingCheckResult result = Graded(name, 0.0, limit, unit, why);
  result.set_passed(false);
  return result;
}

double Fraction(std::uint64_t part, std::uint64_t whole) {
  return whole > 0 ? static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

// The slowest stream by p99, or nothing when the DUT measured no latency.
const proto::StreamLatency* WorstLatency(const proto::Timing& timing) {
  const proto::StreamLatency* worst = nullptr;
  for (const proto::StreamLatency& stream : timing.dut_latency()) {
    if (stream.count() == 0) continue;
    if (worst == nullptr || !(stream.p99_s() <= worst->p99_s())) worst = &stream;
  }
  return worst;
}

proto::TimingCheckResult GradeRealtime(const std::string& name, double limit,
                                       const proto::Timing& timing) {
  // A run too short to have a period proved nothing about it.
  const bool has_period = timing.ticks() >= 2;
  if (name == "loop_period_p99_max_s") {
    if (!has_period) return Unmeasured(name, limit, "s", "no loop period measured");
    return Graded(name, timing.loop_period_p99_s(), limit, "s");
  }
  if (name == "loop_period_max_s") {
    if (!has_period) return Unmeasured(name, limit, "s", "no loop period measured");
    return Graded(name, timing.loop_period_max_s(), limit, "s");
  }
  if (name == "late_tick_fraction_max") {
    if (timing.ticks() == 0) return Unmeasured(name, limit, "fraction", "no tick ran");
    return Graded(name, Fraction(timing.late_ticks(), timing.ticks()), limit, "fraction");
  }
  if (name == "dut_commands_missed_fraction_max") {
    if (timing.control_ticks() == 0) return Unmeasured(name, limit, "fraction", "no control tick");
    return Graded(name, Fraction(timing.dut_commands_missed(), timing.control_ticks()), limit,
                  "fraction");
  }
  const proto::StreamLatency* worst = WorstLatency(timing);
  if (worst == nullptr) return NotEvaluated(name, limit, "s", "the DUT measures no latency");
  return Graded(name, worst->p99_s(), limit, "s", "stream " + worst->stream());
}

}  // namespace

std::vector<proto::TimingCheckResult> GradeTiming(const proto::TimingEnvelopes& limits,
                                                  const proto::Timing& timing) {
  struct Limit {
    const char* name;
    bool set;
    double value;
    const char* unit;
  };
  const Limit all[] = {
      {"loop_period_p99_max_s", limits.has_loop_period_p99_max_s(), limits.loop_period_p99_max_s(),
       "s"},
      {"loop_period_max_s", limits.has_loop_period_max_s(), limits.loop_period_max_s(), "s"},
      {"late_tick_fraction_max", limits.has_late_tick_fraction_max(),
       limits.late_tick_fraction_max(), "fraction"},
      {"dut_latency_p99_max_s", limits.has_dut_latency_p99_max_s(), limits.dut_latency_p99_max_s(),
       "s"},
      {"dut_commands_missed_fraction_max", limits.has_dut_commands_missed_fraction_max(),
       limits.dut_commands_missed_fraction_max(), "fraction"},
  };
  const bool realtime = timing.mode() == "realtime";
  std::vector<proto::TimingCheckResult> results;
  for (const Limit& limit : all) {
    if (!limit.set) continue;
    results.push_back(realtime ? GradeRealtime(limit.name, limit.value, timing)
                               : NotEvaluated(limit.name, limit.value, limit.unit, "lockstep"));
  }
  return results;
}

}  // namespace hilrig::host
