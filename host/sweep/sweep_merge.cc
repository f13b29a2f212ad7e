#include "host/sweep/sweep_merge.h"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include "host/report/sweep_outcome.h"
#include "host/sweep/case_run.h"
#include "host/sweep/shell_words.h"
#include "host/sweep/sweep_cases.h"
#include "host/sweep/sweep_map.h"
#include "host/sweep/sweep_page.h"
#include "host/sweep/sweep_shard.h"
#include "host/sweep/sweep_statistics.h"
#include "rig/file_io.h"
#include "rig/number_text.h"
#include "rig/printable_text.h"

namespace hilrig::host {
namespace {

// A CSV field: quoted when it holds a comma, a quote or a line break, quotes doubled (RFC 4180).
std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

// The envelope names of the sweep's scenarios, each once, in first-seen order.
std::vector<std::string> EnvelopeColumns(const LoadedSweep& sweep) {
  std::vector<std::string> names;
  std::set<std::string> seen;
  for (const SweepScenario& scenario : sweep.scenarios) {
    for (const proto::Envelope& envelope : scenario.spec.envelopes()) {
      if (seen.insert(envelope.name()).second) names.push_back(envelope.name());
    }
  }
  return names;
}

const SweepScenario* ScenarioNamed(const LoadedSweep& sweep, const std::string& name) {
  for (const SweepScenario& scenario : sweep.scenarios) {
    if (scenario.spec.name() == name) return &scenario;
  }
  return nullptr;
}

std::string FailingText(const LoadedSweep& sweep,
                        const std::map<std::uint64_t, proto::SweepCaseResult>& rows,
                        const std::string& hilrig, const std::string& runs_dir) {
  std::ostringstream text;
  for (const auto& [index, row] : rows) {
    if (row.outcome() == proto::SweepCaseResult::PASSED) continue;
    text << "# case " << index << " " << OutcomeName(row.outcome());
    // The detail comes from the case's run (a stop reason may quote a spec's path): one line with
    // every control character escaped, so that nothing in it runs when the file is run.
    if (!row.detail().empty()) text << ": " << rig::PrintableText(row.detail());
    text << "\n" << ReproduceCommand(sweep, row, hilrig, runs_dir) << "\n";
  }
  return text.str();
}

}  // namespace

std::string RunsCsv(const LoadedSweep& sweep,
                    const std::map<std::uint64_t, proto::SweepCaseResult>& rows) {
  const std::vector<std::string> envelopes = EnvelopeColumns(sweep);
  std::ostringstream csv;
  csv << "case,scenario,seed";
  for (const proto::Axis& axis : sweep.spec.axis()) csv << "," << CsvField(axis.path());
  csv << ",outcome";
  for (const std::string& name : envelopes) {
    csv << "," << CsvField(name + ".met") << "," << CsvField(name + ".worst") << ","
        << CsvField(name + ".margin");
  }
  csv << ",detail,real_time_factor,wall_s\n";
  for (const auto& [index, row] : rows) {
    csv << index << "," << CsvField(row.scenario()) << "," << row.seed();
    for (const double value : row.value()) csv << "," << rig::ExactNumber(value);
    csv << "," << OutcomeName(row.outcome());
    for (const std::string& name : envelopes) {
      const proto::SweepCaseResult::Envelope* found = nullptr;
      for (const auto& envelope : row.envelope()) {
        if (envelope.name() == name) found = &envelope;
      }
      if (found == nullptr) {
        csv << ",,,";
        continue;
      }
      csv << "," << (found->met() ? 1 : 0) << "," << rig::ExactNumber(found->worst()) << ","
          << rig::ExactNumber(found->margin());
    }
    csv << "," << CsvField(row.detail()) << "," << rig::ExactNumber(row.real_time_factor()) << ","
        << rig::ExactNumber(row.wall_s()) << "\n";
  }
  return csv.str();
}

std::string ReproduceCommand(const LoadedSweep& sweep, const proto::SweepCaseResult& row,
                             const std::string& hilrig, const std::string& runs_dir) {
  const SweepScenario* scenario = ScenarioNamed(sweep, row.scenario());
  std::string command = ShellQuoted(hilrig) + " run " +
                        ShellQuoted(scenario != nullptr ? scenario->path : row.scenario()) +
                        " --seed " + std::to_string(row.seed());
  std::string sets;
  for (const proto::SweepSet& every_case : sweep.spec.set()) {
    sets +=
        (sets.empty() ? "" : ",") + every_case.path() + "=" + rig::ExactNumber(every_case.value());
  }
  for (int a = 0; a < sweep.spec.axis_size() && a < row.value_size(); ++a) {
    sets += (sets.empty() ? "" : ",") + sweep.spec.axis(a).path() + "=" +
            rig::ExactNumber(row.value(a));
  }
  if (!sets.empty()) command += " --set " + ShellQuoted(sets);
  return command + " --no-reference --out " + ShellQuoted(CaseFolder(runs_dir, row.index()));
}

namespace {

// What makes `row` not the result of its case (the case recomputed from the sweep spec), or
// nothing when it may stand for it.
std::optional<std::string> RowMismatch(const LoadedSweep& sweep, const SweepCaseSpace& cases,
                                       const proto::SweepCaseResult& row) {
  if (row.index() >= cases.case_count()) {
    return "case " + std::to_string(row.index()) + " is not one of the sweep's " +
           std::to_string(cases.case_count()) + " cases";
  }
  const SweepCase expected = cases.CaseAt(row.index());
  const std::string label = "case " + std::to_string(row.index());
  const proto::Scenario& scenario = sweep.scenarios[expected.scenario].spec;
  if (row.scenario() != scenario.name()) return label + " is not of scenario " + scenario.name();
  if (row.seed() != expected.seed) {
    return label + " has seed " + std::to_string(row.seed()) + ", the sweep's " +
           std::to_string(expected.seed);
  }
  if (!std::equal(row.value().begin(), row.value().end(), expected.values.begin(),
                  expected.values.end())) {
    return label + " has other axis values than the sweep's (" + CaseLabel(sweep, expected) + ")";
  }
  if (proto::SweepCaseResult::Outcome_IsValid(row.outcome()) == false ||
      row.outcome() == proto::SweepCaseResult::OUTCOME_UNSPECIFIED) {
    return label + " has no outcome";
  }
  std::set<std::string> names;
  for (const proto::Envelope& envelope : scenario.envelopes()) names.insert(envelope.name());
  bool all_met = true;
  for (const auto& envelope : row.envelope()) {
    if (names.count(envelope.name()) == 0) {
      return label + " names an envelope its scenario does not have";
    }
    all_met = all_met && envelope.met();
  }
  if (row.outcome() == proto::SweepCaseResult::PASSED &&
      (!all_met || row.envelope_size() != scenario.envelopes_size())) {
    return label + " says passed without every envelope met";
  }
  return std::nullopt;
}

}  // namespace

rig::Result<MergedSweep> MergeSweep(const LoadedSweep& sweep, const std::string& out_dir,
                                    const std::string& hilrig) {
  MergedSweep merged;
  const SweepCaseSpace cases(sweep);
  merged.cases = cases.case_count();
  auto found = ReadShardRows(
      out_dir, [&](const proto::SweepCaseResult& row) { return RowMismatch(sweep, cases, row); });
  if (!found) return found.error();
  merged.bad_lines = found.value().bad_lines;
  merged.conflicting_cases = found.value().conflicting_cases.size();
  merged.unreadable_files = found.value().unreadable_files;
  merged.problems = std::move(found.value().problems);
  auto& rows = found.value().rows;
  merged.finished = rows.size();
  for (const auto& [index, row] : rows) {
    if (row.outcome() != proto::SweepCaseResult::PASSED) ++merged.not_passed;
  }
  const std::filesystem::path folder(out_dir);
  const std::string runs_dir = (folder / "runs").string();
  if (auto written = rig::WriteFileAtomically((folder / "runs.csv").string(), RunsCsv(sweep, rows));
      !written.ok()) {
    return written.error();
  }
  if (auto written = rig::WriteFileAtomically((folder / "failing.txt").string(),
                                              FailingText(sweep, rows, hilrig, runs_dir));
      !written.ok()) {
    return written.error();
  }
  std::vector<proto::SweepCaseResult> results;
  results.reserve(rows.size());
  for (auto& [index, row] : rows) results.push_back(std::move(row));
  merged.summary = SummariseSweep(sweep, results);
  merged.summary.set_sweep_cases(merged.cases);
  // The criteria hold for the sweep only when every case ran: a stopped sweep, a missing shard or
  // a refused row leaves cases that could have failed.
  merged.summary.set_complete(merged.finished == merged.cases);
  merged.summary.set_passed(merged.summary.passed() && merged.summary.complete());
  merged.summary.set_rows_refused(merged.bad_lines);
  merged.summary.set_conflicting_cases(merged.conflicting_cases);
  auto json = SummaryJson(merged.summary);
  if (!json) return json.error();
  if (auto written = rig::WriteFileAtomically((folder / "summary.json").string(), json.value());
      !written.ok()) {
    return written.error();
  }
  if (const std::optional<std::string> map = SweepMapSvg(sweep, results)) {
    if (auto written = rig::WriteFileAtomically((folder / kSweepMapFile).string(), *map);
        !written.ok()) {
      return written.error();
    }
  }
  if (auto written =
          rig::WriteFileAtomically((folder / kSweepPageFile).string(),
                                   SweepPageHtml(sweep, results, merged.summary, hilrig, runs_dir));
      !written.ok()) {
    return written.error();
  }
  merged.criteria_met = merged.summary.passed();
  return merged;
}

}  // namespace hilrig::host
