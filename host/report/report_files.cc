#include "host/report/report_files.h"

#include <google/protobuf/util/json_util.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/report/stop_reason.h"
#include "host/report/xml_text.h"
#include "rig/file_io.h"
#include "rig/number_text.h"

namespace hilrig::host {

rig::Result<void> WriteTextFile(const std::string& path, const std::string& content) {
  return rig::WriteFileAtomically(path, content);
}

namespace {

std::string FormatNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g", value);
  return buffer;
}

std::string FormatBounds(const proto::EnvelopeResult& result) {
  std::ostringstream bounds;
  bounds << '[' << (result.has_lower() ? FormatNumber(result.lower()) : "-") << ", "
         << (result.has_upper() ? FormatNumber(result.upper()) : "-") << ']';
  return bounds.str();
}

const char* VerdictName(proto::Verdict verdict) { return verdict == proto::PASS ? "PASS" : "FAIL"; }

double Micros(double seconds) { return seconds * 1e6; }

// The timing or the target checks (`kind`) as test cases.
void AppendCheckCases(const proto::Report& report,
                      const google::protobuf::RepeatedPtrField<proto::TimingCheckResult>& checks,
                      const char* kind, std::ostringstream& cases, int& failures) {
  for (const proto::TimingCheckResult& check : checks) {
    cases << "    <testcase classname=\"" << EscapeXmlText(report.scenario()) << "\" name=\""
          << kind << " " << EscapeXmlText(check.name()) << "\">\n";
    if (!check.evaluated()) {
      cases << "      <skipped message=\"" << EscapeXmlText(check.note()) << "\"/>\n";
    } else if (!check.passed()) {
      ++failures;
      cases << "      <failure message=\"" << EscapeXmlText(FormatTimingCheckLine(check, kind))
            << "\"/>\n";
    }
    cases << "    </testcase>\n";
  }
}

}  // namespace

std::string FormatTimingValue(double value, const std::string& unit) {
  char buffer[48];
  if (unit == "s") {
    std::snprintf(buffer, sizeof(buffer), "%.0f us", Micros(value));
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.3g %%", value * 100);
  }
  return buffer;
}

rig::Result<void> WriteJsonFile(const google::protobuf::Message& message, const std::string& path) {
  std::string json;
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  const auto status = google::protobuf::util::MessageToJsonString(message, &json, options);
  if (!status.ok()) return rig::MakeError("cannot render " + path + ": " + status.ToString());
  return WriteTextFile(path, json);
}

rig::Result<void> ReadJsonFile(const std::string& path, google::protobuf::Message& message) {
  constexpr std::size_t kMaxJsonBytes = std::size_t{64} << 20;
  auto text = rig::ReadRegularFile(path, kMaxJsonBytes);
  if (!text) return text.error();
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = true;
  const auto status = google::protobuf::util::JsonStringToMessage(text.value(), &message, options);
  if (!status.ok()) {
    return rig::MakeError(path + " is not a " + message.GetDescriptor()->name() +
                          " in JSON: " + std::string(status.message()));
  }
  return {};
}

rig::Result<void> WriteJunitXml(const proto::Report& report, const std::string& path) {
  int failures = 0;
  std::ostringstream cases;
  for (const proto::EnvelopeResult& result : report.envelopes()) {
    cases << "    <testcase classname=\"" << EscapeXmlText(report.scenario()) << "\" name=\""
          << EscapeXmlText(result.name()) << "\">\n";
    if (!result.meets_expectation()) {
      ++failures;
      cases << "      <failure message=\"" << EscapeXmlText(FormatEnvelopeLine(result)) << "\"/>\n";
    }
    cases << "    </testcase>\n";
  }
  AppendCheckCases(report, report.timing_checks(), "timing", cases, failures);
  AppendCheckCases(report, report.target_checks(), "target", cases, failures);
  if (report.has_dut_faults()) {
    ++failures;
    cases << "    <testcase classname=\"" << EscapeXmlText(report.scenario())
          << "\" name=\"dut commands finite\">\n      <failure message=\""
          << EscapeXmlText(FormatDutFaultLine(report.dut_faults())) << "\"/>\n    </testcase>\n";
  }
  if (!RunCompleted(report)) {
    ++failures;
    cases << "    <testcase classname=\"" << EscapeXmlText(report.scenario())
          << "\" name=\"run completes\">\n      <failure message=\""
          << EscapeXmlText(report.stop_reason() + " at " + rig::NumberText(report.simulated_s()) +
                           " s simulated")
          << "\"/>\n    </testcase>\n";
  }
  const int tests = report.envelopes_size() + report.timing_checks_size() +
                    report.target_checks_size() + (report.has_dut_faults() ? 1 : 0) +
                    (!RunCompleted(report) ? 1 : 0);
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<testsuites>\n  <testsuite name=\"" << EscapeXmlText(report.scenario()) << "\" tests=\""
      << tests << "\" failures=\"" << failures << "\" time=\"" << report.wall_s() << "\">\n"
      << cases.str() << "  </testsuite>\n</testsuites>\n";
  return WriteTextFile(path, xml.str());
}

std::string FormatDutFaultLine(const proto::DutFaults& faults) {
  return "DUT FAULT  " + std::to_string(faults.non_finite_commands()) + " non-finite command" +
         (faults.non_finite_commands() == 1 ? "" : "s") + " refused, the first at " +
         FormatNumber(faults.first_at_s()) + " s (" + faults.first_field() + "): the run fails";
}

std::string FormatEnvelopeLine(const proto::EnvelopeResult& result) {
  std::string line =
      (result.not_evaluated() ? std::string("NOT EVALUATED") : VerdictName(result.verdict())) +
      "  " + result.name();
  if (result.samples_checked() == 0) {
    line += "  no samples in its window (the run ended before it, or it was cut short)";
  } else {
    line += "  worst " + FormatNumber(result.worst_value()) + " at " +
            FormatNumber(result.worst_at_s()) + " s";
  }
  line += "  limit " + FormatBounds(result);
  if (result.verdict() == proto::FAIL && result.samples_checked() > 0) {
    line += "  first out at " + FormatNumber(result.first_violation_at_s()) + " s";
  }
  if (result.expected() != proto::PASS) {
    line += std::string("  (expected ") + VerdictName(result.expected()) +
            (result.meets_expectation() ? ", as expected)" : ", NOT MET)");
  }
  return line;
}

std::string FormatTimingLine(const proto::Report& report) {
  char buffer[200];
  std::snprintf(buffer, sizeof(buffer),
                "real-time factor %s (%.3g s simulated in %.3g s wall, %s; setup %.3g s)",
                rig::FactorText(report.real_time_factor()).c_str(), report.simulated_s(),
                report.wall_s(), report.stop_reason().c_str(), report.setup_s());
  return buffer;
}

std::string FormatFidelityErrorLine(const proto::FidelityError& error, bool grasp_scene) {
  char buffer[300];
  int length =
      std::snprintf(buffer, sizeof(buffer),
                    "fidelity error vs reference %s%s: ", error.reference_fidelity().c_str(),
                    error.reference_cached() ? " (cached)" : "");
  if (grasp_scene && length > 0) {
    length += std::snprintf(buffer + length, sizeof(buffer) - static_cast<std::size_t>(length),
                            "grasp force RMS %.3g N (max %.3g), load RMS %.3g N (max %.3g), ",
                            error.grasp_force_rms_n(), error.grasp_force_max_n(),
                            error.load_rms_n(), error.load_max_n());
  }
  if (length > 0 && static_cast<std::size_t>(length) < sizeof(buffer)) {
    std::snprintf(buffer + length, sizeof(buffer) - static_cast<std::size_t>(length),
                  "position RMS %.3g m (max %.3g)", error.position_rms_m(), error.position_max_m());
  }
  return buffer;
}

std::string FormatTimingCheckLine(const proto::TimingCheckResult& result, const char* kind) {
  std::string line = !result.evaluated() ? "----" : result.passed() ? "PASS" : "FAIL";
  line += "  " + std::string(kind) + " " + result.name() + "  ";
  if (result.evaluated()) {
    line += FormatTimingValue(result.value(), result.unit());
    if (!result.note().empty()) line += " (" + result.note() + ")";
  } else {
    line += result.note();
  }
  return line + "  limit " + FormatTimingValue(result.limit(), result.unit());
}

namespace {

// What QEMU's counts mean for the real part: under -icount every instruction takes 1 ns of
// virtual time, so a count at the core clock is 1e9 / clock instructions, and a real core needs
// at least a cycle for each.
std::string EmulatedCoreNote(const proto::Target& target) {
  const double instructions_per_count = 1e9 / target.core_clock_hz();
  const double p99_instructions = target.work_p99_cycles() * instructions_per_count;
  const double period_cycles = target.control_period_s() * target.core_clock_hz();
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer),
                " (not cycles: %.3g instructions each, so p99 is %.0f instructions; a real "
                "%.0f MHz core needs at least as many cycles, %.3g %% of %.0f us or more)",
                instructions_per_count, p99_instructions, target.core_clock_hz() / 1e6,
                period_cycles > 0 ? 100 * p99_instructions / period_cycles : 0.0,
                target.control_period_s() * 1e6);
  return buffer;
}

}  // namespace

std::string FormatTargetLine(const proto::Target& target) {
  char buffer[320];
  std::string line = "target " + target.board();
  if (target.core_clock_hz() > 0) {
    std::snprintf(buffer, sizeof(buffer), " at %.0f MHz", target.core_clock_hz() / 1e6);
    line += buffer;
  }
  if (target.steps_measured() == 0) {
    line += ": work per control step not measured";
  } else {
    std::snprintf(buffer, sizeof(buffer), ": work per control step p50 %u, p99 %u, max %u %s",
                  target.work_p50_cycles(), target.work_p99_cycles(), target.work_max_cycles(),
                  target.emulated_core() ? "SysTick counts of QEMU's virtual time" : "cycles");
    line += buffer;
    if (target.emulated_core() && target.core_clock_hz() > 0) {
      line += EmulatedCoreNote(target);
    } else if (target.core_clock_hz() > 0) {
      std::snprintf(buffer, sizeof(buffer), " (%.3g %%, %.3g %%, %.3g %% of %.0f us)",
                    100 * target.work_p50_fraction(), 100 * target.work_p99_fraction(),
                    100 * target.work_max_fraction(), target.control_period_s() * 1e6);
      line += buffer;
    }
    line += " over " + std::to_string(target.steps_measured()) + " steps";
  }
  if (target.flash_used_bytes() > 0 || target.ram_used_bytes() > 0) {
    line += "; flash " + std::to_string(target.flash_used_bytes()) + " B, RAM " +
            std::to_string(target.ram_used_bytes()) + " B";
  }
  return line;
}

std::vector<std::string> FormatRealtimeTiming(const proto::Timing& timing) {
  if (timing.mode() != "realtime") return {};
  std::vector<std::string> lines;
  char buffer[240];
  const double late_percent =
      timing.ticks() > 0
          ? 100.0 * static_cast<double>(timing.late_ticks()) / static_cast<double>(timing.ticks())
          : 0.0;
  std::snprintf(buffer, sizeof(buffer),
                "loop period p50 %.0f us, p99 %.0f us, max %.0f us (target %.0f us); late ticks "
                "%llu (%.3g %%) over %.0f us, stalls %llu",
                Micros(timing.loop_period_p50_s()), Micros(timing.loop_period_p99_s()),
                Micros(timing.loop_period_max_s()), Micros(timing.period_s()),
                static_cast<unsigned long long>(timing.late_ticks()), late_percent,
                Micros(timing.late_threshold_s()),
                static_cast<unsigned long long>(timing.stalls()));
  lines.emplace_back(buffer);
  std::snprintf(buffer, sizeof(buffer),
                "tick work p50 %.0f us, p99 %.0f us, max %.0f us; dut commands missed %llu of %llu "
                "control ticks",
                Micros(timing.work_p50_s()), Micros(timing.work_p99_s()),
                Micros(timing.work_max_s()),
                static_cast<unsigned long long>(timing.dut_commands_missed()),
                static_cast<unsigned long long>(timing.control_ticks()));
  lines.emplace_back(buffer);
  if (!timing.scheduling().empty()) lines.push_back("scheduling: " + timing.scheduling());
  if (timing.dut_latency_size() == 0) lines.emplace_back("dut latency: not measured by this DUT");
  for (const proto::StreamLatency& stream : timing.dut_latency()) {
    std::snprintf(buffer, sizeof(buffer),
                  "dut latency %s: p50 %.0f us, p99 %.0f us, max %.0f us (%llu)",
                  stream.stream().c_str(), Micros(stream.p50_s()), Micros(stream.p99_s()),
                  Micros(stream.max_s()), static_cast<unsigned long long>(stream.count()));
    lines.emplace_back(buffer);
  }
  return lines;
}

std::string FormatObjectLine(const proto::ObjectOutcome& outcome) {
  char buffer[300];
  if (outcome.damage() == "none") {
    std::snprintf(buffer, sizeof(buffer), "object %s: undamaged, %s, peak %.3g N per pad",
                  outcome.fixture().c_str(), outcome.final_state().c_str(),
                  outcome.peak_normal_force_n());
  } else {
    std::snprintf(buffer, sizeof(buffer), "object %s: %s at %.3g s, %s, peak %.3g N per pad",
                  outcome.fixture().c_str(), outcome.damage().c_str(), outcome.damaged_at_s(),
                  outcome.final_state().c_str(), outcome.peak_normal_force_n());
  }
  std::string line = buffer;
  if (outcome.has_damage_force_n()) {
    std::snprintf(buffer, sizeof(buffer), " (damaged at %.3g N, margin %.3g N)",
                  outcome.damage_force_n(), outcome.damage_margin_n());
    line += buffer;
  }
  return line;
}

}  // namespace hilrig::host
