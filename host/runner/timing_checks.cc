#include "host/runner/timing_checks.h"

#include <cmath>
#include <optional>
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

// What a real-time run measured for one check: a value (with an optional note), nothing (the run
// proved nothing about it: it fails), or a figure this DUT does not have (not evaluated).
struct Measured {
  std::optional<double> value;
  std::string note;
  bool not_applicable = false;
};

Measured LoopPeriodP99(const proto::Timing& timing) {
  if (timing.ticks() < 2) return {std::nullopt, "no loop period measured"};
  return {timing.loop_period_p99_s(), ""};
}

Measured LoopPeriodMax(const proto::Timing& timing) {
  if (timing.ticks() < 2) return {std::nullopt, "no loop period measured"};
  return {timing.loop_period_max_s(), ""};
}

Measured LateTickFraction(const proto::Timing& timing) {
  if (timing.ticks() == 0) return {std::nullopt, "no tick ran"};
  return {Fraction(timing.late_ticks(), timing.ticks()), ""};
}

Measured DutLatencyP99(const proto::Timing& timing) {
  const proto::StreamLatency* worst = WorstLatency(timing);
  if (worst == nullptr) return {std::nullopt, "the DUT measures no latency", true};
  return {worst->p99_s(), "stream " + worst->stream()};
}

Measured MissedCommandFraction(const proto::Timing& timing) {
  if (timing.control_ticks() == 0) return {std::nullopt, "no control tick"};
  return {Fraction(timing.dut_commands_missed(), timing.control_ticks()), ""};
}

struct GradedLimit {
  const char* name;
  const char* unit;
  std::optional<double> TimingLimits::*limit;
  Measured (*measure)(const proto::Timing&);
};

// In the order of proto::TimingEnvelopes' fields.
constexpr GradedLimit kTimingLimits[] = {
    {"loop_period_p99_max_s", "s", &TimingLimits::loop_period_p99_max_s, &LoopPeriodP99},
    {"loop_period_max_s", "s", &TimingLimits::loop_period_max_s, &LoopPeriodMax},
    {"late_tick_fraction_max", "fraction", &TimingLimits::late_tick_fraction_max,
     &LateTickFraction},
    {"dut_latency_p99_max_s", "s", &TimingLimits::dut_latency_p99_max_s, &DutLatencyP99},
    {"dut_commands_missed_fraction_max", "fraction",
     &TimingLimits::dut_commands_missed_fraction_max, &MissedCommandFraction},
};

proto::TimingCheckResult GradeRealtime(const GradedLimit& check, double limit,
                                       const proto::Timing& timing) {
  Measured measured = check.measure(timing);
  if (measured.not_applicable) return NotEvaluated(check.name, limit, check.unit, measured.note);
  if (!measured.value) return Unmeasured(check.name, limit, check.unit, measured.note);
  return Graded(check.name, *measured.value, limit, check.unit, std::move(measured.note));
}

}  // namespace

proto::Target TargetSection(const TargetSummary& target, double control_period_s) {
  proto::Target section;
  section.set_board(target.board);
  section.set_core_clock_hz(target.core_clock_hz);
  section.set_flash_used_bytes(target.flash_used_bytes);
  section.set_ram_used_bytes(target.ram_used_bytes);
  section.set_stack_bytes(target.stack_bytes);
  section.set_control_period_s(control_period_s);
  section.set_steps_measured(target.steps_measured);
  section.set_work_p50_cycles(target.work_p50_cycles);
  section.set_work_p99_cycles(target.work_p99_cycles);
  section.set_work_max_cycles(target.work_max_cycles);
  section.set_emulated_core(target.emulated_core);
  const double period_cycles = control_period_s * target.core_clock_hz;
  if (period_cycles > 0) {
    section.set_work_p50_fraction(target.work_p50_cycles / period_cycles);
    section.set_work_p99_fraction(target.work_p99_cycles / period_cycles);
    section.set_work_max_fraction(target.work_max_cycles / period_cycles);
  }
  return section;
}

std::vector<proto::TimingCheckResult> GradeTarget(const TargetLimits& limits,
                                                  const proto::Target* target) {
  struct Limit {
    const char* name;
    std::optional<double> TargetLimits::*limit;
    double (proto::Target::*fraction)() const;
  };
  constexpr Limit kLimits[] = {
      {"work_p99_fraction_max", &TargetLimits::work_p99_fraction_max,
       &proto::Target::work_p99_fraction},
      {"work_max_fraction_max", &TargetLimits::work_max_fraction_max,
       &proto::Target::work_max_fraction},
  };
  std::vector<proto::TimingCheckResult> results;
  for (const Limit& check : kLimits) {
    const std::optional<double>& limit = limits.*check.limit;
    if (!limit) continue;
    if (target == nullptr) {
      results.push_back(NotEvaluated(check.name, *limit, "fraction", "the DUT runs on the host"));
    } else if (target->core_clock_hz() == 0) {
      // A DUT on a serial line that is no MCU (dut_emu --serial) says so by giving no clock.
      results.push_back(NotEvaluated(check.name, *limit, "fraction",
                                     "the DUT gives no core clock: it measures no work"));
    } else if (target->steps_measured() == 0) {
      // A target that claims a clock owes the figure; a missing one must not pass.
      results.push_back(Unmeasured(check.name, *limit, "fraction",
                                   "the target gave a core clock but measured no work per step"));
    } else {
      results.push_back(Graded(check.name, (target->*check.fraction)(), *limit, "fraction",
                               "target " + target->board()));
    }
  }
  return results;
}

std::vector<proto::TimingCheckResult> GradeTiming(const TimingLimits& limits,
                                                  const proto::Timing& timing) {
  const bool realtime = timing.mode() == "realtime";
  std::vector<proto::TimingCheckResult> results;
  for (const GradedLimit& check : kTimingLimits) {
    const std::optional<double>& limit_or_none = limits.*check.limit;
    if (!limit_or_none) continue;
    const double limit = *limit_or_none;
    results.push_back(realtime ? GradeRealtime(check, limit, timing)
                               : NotEvaluated(check.name, limit, check.unit, "lockstep"));
  }
  return results;
}

}  // namespace hilrig::host
