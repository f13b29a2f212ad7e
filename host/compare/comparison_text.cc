#include "host/compare/comparison_text.h"

#include <algorithm>
#include <string>

#include "host/compare/change.h"
#include "host/report/sweep_outcome.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// `text` and spaces to `width`, at least two.
std::string Padded(std::string text, std::size_t width) {
  text.append(text.size() + 2 <= width ? width - text.size() : 2, ' ');
  return text;
}

std::string Arrow(const std::string& base, const std::string& candidate) {
  return base == candidate ? base : base + " -> " + candidate;
}

std::string NumbersMoved(double base, double candidate) {
  return Arrow(rig::NumberText(base), rig::NumberText(candidate));
}

const char* MetText(bool met) { return met ? "met" : "not met"; }

const char* VerdictText(proto::Verdict verdict) { return verdict == proto::FAIL ? "FAIL" : "PASS"; }

std::string CheckLine(const proto::CheckChange& check) {
  std::string line = "  " + Padded(ChangeText(check.change()), 26);
  const bool timing = check.kind() == proto::CheckChange::TIMING;
  const bool envelope = !timing && check.kind() != proto::CheckChange::TARGET;
  line += Padded(std::string(envelope ? "" : timing ? "timing " : "target ") + check.name(), 28);
  if (check.change() == proto::ONLY_IN_BASE || check.change() == proto::ONLY_IN_CANDIDATE) {
    return line;
  }
  if (!envelope) {
    return line + Padded(Arrow(MetText(check.base_met()), MetText(check.candidate_met())), 20) +
           "value " + NumbersMoved(check.base_worst(), check.candidate_worst());
  }
  return line +
         Padded(Arrow(VerdictText(check.base_verdict()), VerdictText(check.candidate_verdict())),
                14) +
         "worst " + NumbersMoved(check.base_worst(), check.candidate_worst()) + "  margin " +
         NumbersMoved(check.base_margin(), check.candidate_margin());
}

void AddTraceLines(const proto::TraceComparison& trace, std::vector<std::string>& lines) {
  if (!trace.compared()) {
    lines.push_back("traces: not compared: " + trace.problem());
    return;
  }
  std::string head = "traces: " + std::to_string(trace.rows_compared()) + " rows compared (base " +
                     std::to_string(trace.base_rows()) + ", candidate " +
                     std::to_string(trace.candidate_rows()) + "), " +
                     std::to_string(trace.signals_compared()) + " signals, " +
                     std::to_string(trace.difference_size()) + " differ";
  if (trace.has_times_part_at_s()) {
    head += "; their times part at " + rig::NumberText(trace.times_part_at_s()) + " s";
  }
  lines.push_back(head);
  if (!trace.problem().empty()) lines.push_back("  stopped early: " + trace.problem());
  int listed = 0;
  for (const auto& difference : trace.difference()) {
    if (listed++ == kMaxListedSignals) {
      lines.push_back("  ... and " + std::to_string(trace.difference_size() - kMaxListedSignals) +
                      " more");
      break;
    }
    lines.push_back("  " + Padded(difference.signal(), 28) +
                    (difference.has_diverges_at_s()
                         ? "diverges at " + rig::NumberText(difference.diverges_at_s()) + " s, "
                         : std::string("within tolerance, ")) +
                    "largest difference " + rig::NumberText(difference.max_abs_difference()) +
                    " at " + rig::NumberText(difference.max_at_s()) + " s");
  }
  for (const auto& name : trace.only_in_base()) lines.push_back("  only in base: " + name);
  for (const auto& name : trace.only_in_candidate())
    lines.push_back("  only in candidate: " + name);
}

std::string RateText(std::uint64_t met, std::uint64_t cases) {
  const double rate = cases == 0 ? 0 : static_cast<double>(met) / static_cast<double>(cases);
  return rig::NumberText(100 * rate) + " % (" + std::to_string(met) + "/" + std::to_string(cases) +
         ")";
}

// The row's word. A pass rate that held while a gated margin quantile shrank beyond the tolerance
// is among the reasons the candidate is worse, so the row must not read "same".
std::string EnvelopeChangeText(const proto::PassRateChange& row) {
  const bool margin_worse = std::any_of(
      row.quantile().begin(), row.quantile().end(),
      [](const auto& shift) { return shift.gated() && shift.change() == proto::WORSE; });
  if (margin_worse && row.change() != proto::WORSE && row.change() != proto::ONLY_IN_BASE) {
    return "WORSE (margin)";
  }
  return ChangeText(row.change());
}

void AddEnvelopeLines(const proto::PassRateChange& row, std::vector<std::string>& lines) {
  std::string line = "  " + Padded(EnvelopeChangeText(row), 26) +
                     Padded(row.scenario() + "/" + row.envelope(), 36);
  if (row.change() == proto::ONLY_IN_BASE) {
    lines.push_back(line);
    return;
  }
  lines.push_back(line + "pass " +
                  Arrow(RateText(row.base_met(), row.base_cases()),
                        RateText(row.candidate_met(), row.candidate_cases())) +
                  "  p " + rig::NumberText(row.p_value()) +
                  (row.expected_fail() ? "  (expected to fail: margins not graded)" : ""));
  if (row.quantile_size() == 0) return;
  std::string margins = "      margin";
  for (const auto& shift : row.quantile()) {
    margins += "  " + shift.quantile() + " " + NumbersMoved(shift.base(), shift.candidate());
    if (shift.change() == proto::WORSE) margins += shift.gated() ? " (WORSE)" : " (ungated)";
  }
  lines.push_back(margins);
}

// "case 3" or, where the sweeps number it differently, "case 3 -> 5".
std::string CaseNumbers(const proto::CaseChange& change) {
  if (!change.has_candidate_case()) return "case " + std::to_string(change.base_case());
  if (!change.has_base_case()) return "case " + std::to_string(change.candidate_case());
  return "case " +
         Arrow(std::to_string(change.base_case()), std::to_string(change.candidate_case()));
}

std::string OutcomesMoved(const proto::CaseChange& change) {
  if (!change.has_candidate_case()) return OutcomeName(change.base_outcome());
  if (!change.has_base_case()) return OutcomeName(change.candidate_outcome());
  return Arrow(OutcomeName(change.base_outcome()), OutcomeName(change.candidate_outcome()));
}

// "case 3: hover, seed 2, vehicle.mass_kg=0.6: passed -> failed".
std::string CaseLine(const proto::CaseChange& change,
                     const google::protobuf::RepeatedPtrField<std::string>& axes) {
  std::string line =
      CaseNumbers(change) + ": " + change.scenario() + ", seed " + std::to_string(change.seed());
  for (int a = 0; a < axes.size() && a < change.value_size(); ++a) {
    line += ", " + axes[a] + "=" + rig::NumberText(change.value(a));
  }
  return line + ": " + OutcomesMoved(change);
}

void AddCaseList(const std::string& title, std::uint64_t count,
                 const google::protobuf::RepeatedPtrField<proto::CaseChange>& listed,
                 const google::protobuf::RepeatedPtrField<std::string>& axes,
                 std::vector<std::string>& lines) {
  if (count == 0) return;
  lines.push_back("  " + title + ": " + std::to_string(count));
  for (const proto::CaseChange& change : listed) lines.push_back("    " + CaseLine(change, axes));
  const auto shown = static_cast<std::uint64_t>(listed.size());
  if (count > shown) lines.push_back("    ... and " + std::to_string(count - shown) + " more");
}

void AddCaseLines(const proto::CaseChanges& cases, std::vector<std::string>& lines) {
  if (!cases.matched()) {
    lines.push_back("cases: not matched: " + cases.problem());
    return;
  }
  std::string head = "cases: " + std::to_string(cases.matched_cases()) +
                     " in both sweeps, matched by scenario, seed and axis values";
  if (cases.now_failing_count() + cases.now_passing_count() + cases.only_in_base_count() +
          cases.only_in_candidate_count() ==
      0) {
    lines.push_back(head + "; no verdict changed");
    return;
  }
  lines.push_back(head + "; " + std::to_string(cases.now_failing_count()) + " now failing, " +
                  std::to_string(cases.now_passing_count()) + " now passing, " +
                  std::to_string(cases.only_in_base_count()) + " only in the base, " +
                  std::to_string(cases.only_in_candidate_count()) +
                  " only in the candidate (listed, not graded: the pass rates, margins and "
                  "criteria decide the verdict)");
  AddCaseList("now failing (passed in the base)", cases.now_failing_count(), cases.now_failing(),
              cases.axis(), lines);
  AddCaseList("now passing (did not pass in the base)", cases.now_passing_count(),
              cases.now_passing(), cases.axis(), lines);
  AddCaseList("only in the base", cases.only_in_base_count(), cases.only_in_base(), cases.axis(),
              lines);
  AddCaseList("only in the candidate", cases.only_in_candidate_count(), cases.only_in_candidate(),
              cases.axis(), lines);
}

}  // namespace

std::vector<std::string> RunComparisonLines(const proto::RunComparison& comparison) {
  std::vector<std::string> lines;
  lines.push_back(
      "run " + Arrow(comparison.scenario(), comparison.candidate_scenario()) + ", seed " +
      Arrow(std::to_string(comparison.base_seed()), std::to_string(comparison.candidate_seed())) +
      ": " + Arrow(comparison.base_stop_reason(), comparison.candidate_stop_reason()) + ", " +
      Arrow(comparison.base_passed() ? "PASS" : "FAIL",
            comparison.candidate_passed() ? "PASS" : "FAIL"));
  for (const auto& check : comparison.check()) lines.push_back(CheckLine(check));
  AddTraceLines(comparison.trace(), lines);
  return lines;
}

std::vector<std::string> SweepComparisonLines(const proto::SweepComparison& comparison) {
  std::vector<std::string> lines;
  lines.push_back("sweep " + Arrow(comparison.sweep(), comparison.candidate_sweep()) + ": cases " +
                  Arrow(std::to_string(comparison.base_cases()) + " of " +
                            std::to_string(comparison.base_sweep_cases()),
                        std::to_string(comparison.candidate_cases()) + " of " +
                            std::to_string(comparison.candidate_sweep_cases())));
  for (const auto& row : comparison.envelope()) AddEnvelopeLines(row, lines);
  for (const auto& row : comparison.criterion()) {
    lines.push_back("  " + Padded(ChangeText(row.change()), 26) + "criterion[" +
                    std::to_string(row.criterion()) + "] (" + row.scenario() + "/" +
                    row.envelope() + ") " +
                    (row.change() == proto::ONLY_IN_BASE
                         ? std::string("only in base")
                         : Arrow(MetText(row.base_passed()), MetText(row.candidate_passed()))));
  }
  if (comparison.has_cases()) AddCaseLines(comparison.cases(), lines);
  return lines;
}

std::vector<std::string> SuiteComparisonLines(const proto::SuiteComparison& comparison) {
  const auto names = [](const google::protobuf::RepeatedPtrField<std::string>& list) {
    std::string joined;
    for (const std::string& name : list) joined += (joined.empty() ? "" : ", ") + name;
    return list.empty() ? std::string("none") : joined;
  };
  std::vector<std::string> lines = {
      "folder run: " + std::to_string(comparison.scene_size()) +
      " scenes in both; only in the base: " + names(comparison.only_in_base()) +
      "; only in the candidate: " + names(comparison.only_in_candidate())};
  for (const proto::SuiteComparison::Scene& scene : comparison.scene()) {
    lines.push_back(scene.name() + ": " + (scene.run().worse() ? "WORSE" : "not worse"));
    for (const std::string& line : RunComparisonLines(scene.run())) lines.push_back("  " + line);
  }
  return lines;
}

std::vector<std::string> VerdictLines(
    bool worse, const google::protobuf::RepeatedPtrField<std::string>& reasons,
    const proto::CompareTolerances& tolerances, bool sweeps) {
  std::string stated =
      "margins may shrink by " + rig::NumberText(100 * tolerances.margin_fraction()) + " %";
  if (sweeps) {
    stated += ", pass rates drop by " + rig::NumberText(100 * tolerances.pass_rate_drop()) +
              " points or without significance at " +
              rig::NumberText(100 * tolerances.confidence()) + " %";
  }
  if (!worse) return {"candidate is not worse than the base (" + stated + ")"};
  std::vector<std::string> lines = {"candidate is WORSE than the base (" + stated + "):"};
  for (const auto& reason : reasons) lines.push_back("  " + reason);
  return lines;
}

}  // namespace hilrig::host
