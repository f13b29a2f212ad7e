#include "host/sweep/sweep_page.h"

#include <map>
#include <optional>
#include <set>
#include <utility>

#include "host/report/histogram_plot.h"
#include "host/report/html_page.h"
#include "host/report/signal_unit.h"
#include "host/report/sweep_outcome.h"
#include "host/sweep/case_run.h"
#include "host/sweep/sweep_map.h"
#include "host/sweep/sweep_merge.h"
#include "host/sweep/sweep_statistics.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// The page's verdict colours (html_page.cc), for the histograms' bars.
constexpr const char* kMetColor = "#1A7F37";
constexpr const char* kNotMetColor = "#CF222E";

// As `hilrig sweep` prints it: missing cases leave the criteria ungraded.
PageVerdict SweepVerdict(const proto::SweepSummary& summary) {
  if (summary.cases() < summary.sweep_cases()) return {"INCOMPLETE", Tone::kNeutral};
  return summary.passed() ? PageVerdict{"PASS", Tone::kPass} : PageVerdict{"FAIL", Tone::kFail};
}

// The envelope `name` of the first scenario named `scenario` that has one: its signal and limits.
const proto::Envelope* EnvelopeSpecOf(const LoadedSweep& sweep, const std::string& scenario,
                                      const std::string& name) {
  for (const SweepScenario& candidate : sweep.scenarios) {
    if (candidate.spec.name() != scenario) continue;
    for (const proto::Envelope& envelope : candidate.spec.envelopes()) {
      if (envelope.name() == name) return &envelope;
    }
  }
  return nullptr;
}

std::string UnitOf(const LoadedSweep& sweep, const std::string& scenario,
                   const std::string& envelope) {
  const proto::Envelope* spec = EnvelopeSpecOf(sweep, scenario, envelope);
  return spec != nullptr ? SignalUnit(spec->signal()) : "";
}

std::string Percent(double fraction) { return PageNumber(100 * fraction) + " %"; }

// "[99.6 %, 100 %]"; appended piecewise: GCC 12 warns falsely (-Wrestrict) on "[" + string.
std::string IntervalText(double lower, double upper) {
  std::string text = "[";
  text.append(Percent(lower)).append(", ").append(Percent(upper)).append("]");
  return text;
}

std::string Heading(const LoadedSweep& sweep, const std::vector<proto::SweepCaseResult>& results,
                    const proto::SweepSummary& summary) {
  const PageVerdict verdict = SweepVerdict(summary);
  std::map<std::string, std::uint64_t> outcomes;  // by name: the same order on every page
  for (const proto::SweepCaseResult& row : results) ++outcomes[OutcomeName(row.outcome())];
  std::string counts;
  for (const auto& [name, count] : outcomes) {
    counts += (counts.empty() ? "" : ", ") + std::to_string(count) + " " + name;
  }
  std::string html = "<h1>Sweep " + HtmlText(sweep.spec.name()) + " " +
                     HtmlBadge(verdict.word, verdict.tone) + "</h1>\n<p class=\"sub\">" +
                     std::to_string(summary.cases()) + " of " +
                     std::to_string(summary.sweep_cases()) + " cases finished";
  if (!counts.empty()) html += ": " + HtmlText(counts);
  html += "</p>\n";
  if (verdict.tone == Tone::kNeutral) {
    html +=
        "<p>The sweep is incomplete (stopped, or a shard is missing): its criteria are not "
        "graded as met.</p>\n";
  }
  if (summary.unknown_cases() > 0) {
    html += "<p>" + std::to_string(summary.unknown_cases()) +
            " results name a scenario the sweep does not have; they are left out.</p>\n";
  }
  return html;
}

std::string CriteriaSection(const LoadedSweep& sweep, const proto::SweepSummary& summary) {
  std::string html = "<h2>Criteria</h2>\n";
  if (summary.check_size() == 0) {
    return html +
           "<p>The sweep sets no criterion (or none could be checked): it cannot pass.</p>\n";
  }
  std::vector<std::vector<HtmlCell>> rows;
  for (const proto::SweepCriterionCheck& check : summary.check()) {
    const bool rate = check.kind() == proto::SweepCriterionCheck::PASS_RATE;
    const std::string unit = rate ? "" : UnitOf(sweep, check.scenario(), check.envelope());
    rows.push_back(
        {check.passed() ? TextCell("PASS", Tone::kPass) : TextCell("FAIL", Tone::kFail),
         NumberCell(check.criterion()), TextCell(check.scenario()), TextCell(check.envelope()),
         TextCell(rate ? "pass rate (Wilson lower bound)" : "margin quantile"),
         check.has_measured() ? NumberCell(check.measured(), unit) : TextCell("not measured"),
         NumberCell(check.limit(), unit), TextCell(check.note())});
  }
  return html + HtmlTable({"verdict", "criterion", "scenario", "envelope", "check", "measured",
                           "at least", "note"},
                          rows);
}

HtmlCell MarginCell(const proto::SweepEnvelopeStats& stats, double value) {
  return stats.has_margin() ? NumberCell(value) : TextCell("-");
}

// "50 / 63"; appended piecewise, as IntervalText.
std::string MetText(const proto::SweepEnvelopeStats& stats) {
  std::string text = std::to_string(stats.met());
  text.append(" / ").append(std::to_string(stats.cases()));
  return text;
}

std::string EnvelopeSection(const LoadedSweep& sweep, const proto::SweepSummary& summary) {
  std::string html = "<h2>Envelopes</h2>\n";
  if (summary.envelope_size() == 0) {
    return html + "<p>The sweep's scenarios have no envelope.</p>\n";
  }
  std::vector<std::vector<HtmlCell>> rows;
  for (const proto::SweepEnvelopeStats& stats : summary.envelope()) {
    const std::string unit = UnitOf(sweep, stats.scenario(), stats.envelope());
    const Tone tone = stats.cases() == 0             ? Tone::kNeutral
                      : stats.met() == stats.cases() ? Tone::kPass
                                                     : Tone::kFail;
    const proto::SweepMarginQuantiles& margin = stats.margin();
    const std::string envelope =
        stats.expected_fail() ? stats.envelope() + " (expect FAIL)" : stats.envelope();
    rows.push_back({TextCell(stats.scenario()),
                    TextCell(envelope),
                    TextCell(unit),
                    {HtmlText(MetText(stats)), Tone::kPlain, true, 1},
                    {HtmlText(Percent(stats.pass_rate())), tone, true, 1},
                    {HtmlText(IntervalText(stats.pass_rate_lower(), stats.pass_rate_upper())),
                     Tone::kPlain, true, 1},
                    MarginCell(stats, margin.min()),
                    MarginCell(stats, margin.q01()),
                    MarginCell(stats, margin.q10()),
                    MarginCell(stats, margin.q50()),
                    NumberCell(static_cast<double>(stats.not_run()))});
  }
  return html +
         HtmlTable({"scenario", "envelope", "unit", "met / cases", "pass rate", "95 % interval",
                    "margin min", "1 %", "10 %", "50 %", "not run"},
                   rows) +
         "<p class=\"sub\">A case meets an envelope when the envelope's verdict is the one its "
         "spec expects; a case that did not run meets none. The interval is the pass rate's Wilson "
         "score interval. The margin is how far the worst value stayed inside the limits "
         "(negative: outside), in the envelope's unit, with its low quantiles over the cases that "
         "ran.</p>\n";
}

// The worst values of the envelope over the cases of its scenario that ran, met and not met.
HistogramPlot WorstValuePlot(const LoadedSweep& sweep,
                             const std::vector<proto::SweepCaseResult>& results,
                             const proto::SweepEnvelopeStats& stats, bool name_scenario) {
  HistogramPlot plot;
  plot.title = name_scenario ? stats.scenario() + ": " + stats.envelope() : stats.envelope();
  const std::string unit = UnitOf(sweep, stats.scenario(), stats.envelope());
  plot.x_label = "worst value" + (unit.empty() ? "" : " (" + unit + ")");
  plot.groups = {{"met", kMetColor, {}}, {"not met", kNotMetColor, {}}};
  for (const proto::SweepCaseResult& row : results) {
    if (row.scenario() != stats.scenario() || !CaseRan(row.outcome())) continue;
    for (const proto::SweepCaseResult::Envelope& envelope : row.envelope()) {
      if (envelope.name() != stats.envelope()) continue;
      plot.groups[envelope.met() ? 0 : 1].values.push_back(envelope.worst());
      break;  // a row that lists an envelope twice counts the first, as the summary does
    }
  }
  const std::string suffix = unit.empty() ? "" : " " + unit;
  if (const proto::Envelope* spec = EnvelopeSpecOf(sweep, stats.scenario(), stats.envelope())) {
    if (spec->has_lower()) {
      plot.lines.push_back({"lower " + rig::NumberText(spec->lower()) + suffix, spec->lower()});
    }
    if (spec->has_upper()) {
      plot.lines.push_back({"upper " + rig::NumberText(spec->upper()) + suffix, spec->upper()});
    }
  }
  return plot;
}

std::string HistogramSection(const LoadedSweep& sweep,
                             const std::vector<proto::SweepCaseResult>& results,
                             const proto::SweepSummary& summary) {
  if (summary.envelope_size() == 0) return "";
  std::string html = "<h2>Worst values</h2>\n";
  if (results.empty()) return html + "<p>No case has finished: nothing to draw.</p>\n";
  std::set<std::string> scenarios;
  for (const proto::SweepEnvelopeStats& stats : summary.envelope())
    scenarios.insert(stats.scenario());
  html +=
      "<p class=\"sub\">Each envelope's worst value per case that ran, the cases that met the "
      "envelope in green, the others in red; dashed lines: the envelope's limits.</p>\n"
      "<div class=\"plots\">\n";
  int index = 0;
  for (const proto::SweepEnvelopeStats& stats : summary.envelope()) {
    const HistogramPlot plot = WorstValuePlot(sweep, results, stats, scenarios.size() > 1);
    html += "<figure>\n";
    if (plot.groups[0].values.empty() && plot.groups[1].values.empty()) {
      html += "<p>" + HtmlText(plot.title) + ": no case that ran recorded it.</p>\n";
    } else {
      html += InlineSvg(RenderHistogramSvg(plot), "hist" + std::to_string(index++) + "-");
    }
    html += "</figure>\n";
  }
  return html + "</div>\n";
}

// The names of the axes other than the map's, "a, b".
std::string OtherAxes(const proto::Sweep& spec, std::pair<int, int> map_axes) {
  std::string names;
  for (int a = 0; a < spec.axis_size(); ++a) {
    if (a == map_axes.first || a == map_axes.second) continue;
    names += (names.empty() ? "" : ", ") + spec.axis(a).path();
  }
  return names;
}

std::string MapSection(const LoadedSweep& sweep,
                       const std::vector<proto::SweepCaseResult>& results) {
  const auto axes = SweepMapAxes(sweep.spec);
  const std::optional<std::string> svg = SweepMapSvg(sweep, results);
  if (!axes || !svg) return "";
  std::string html = "<h2>Pass map</h2>\n<p class=\"sub\">A cell per point of " +
                     HtmlText(sweep.spec.axis(axes->first).path()) + " (across) and " +
                     HtmlText(sweep.spec.axis(axes->second).path()) +
                     " (up): blue where every case of the point passed, vermillion where none "
                     "did, a blend of the two for a share, grey where no case finished. A point "
                     "holds the case of every seed and scenario: its cell reads pass or fail for "
                     "one case, k/n when k of its n cases passed.";
  const std::string others = OtherAxes(sweep.spec, *axes);
  if (!others.empty()) {
    html +=
        " The sweep has more axes than a map shows: it draws the first two with listed or "
        "grid values, and a point holds the cases of every value of the others (" +
        HtmlText(others) + ").";
  }
  return html + " The map is also a file of its own, " + HtmlLink(kSweepMapFile, kSweepMapFile) +
         ".</p>\n<figure>\n" + InlineSvg(*svg, "map-") + "</figure>\n";
}

// The case's number, linked to its run folder's page where the case ran (a failing case that ran
// is run again into runs/case-N; one that did not run has no folder).
HtmlCell CaseCell(const proto::SweepCaseResult& row) {
  const std::string index = std::to_string(row.index());
  if (!CaseRan(row.outcome()) && row.outcome() != proto::SweepCaseResult::STOPPED) {
    return {index, Tone::kPlain, true, 1};
  }
  return {HtmlLink(CaseFolder("runs", row.index()) + "/index.html", index), Tone::kPlain, true, 1};
}

std::string FailingSection(const LoadedSweep& sweep,
                           const std::vector<proto::SweepCaseResult>& results,
                           const std::string& hilrig, const std::string& runs_dir) {
  std::vector<const proto::SweepCaseResult*> failing;
  for (const proto::SweepCaseResult& row : results) {
    if (row.outcome() != proto::SweepCaseResult::PASSED) failing.push_back(&row);
  }
  std::string html = "<h2>Cases that did not pass</h2>\n";
  if (failing.empty()) return html + "<p>None.</p>\n";
  std::vector<std::string> headers = {"case", "scenario", "seed"};
  for (const proto::Axis& axis : sweep.spec.axis()) headers.push_back(axis.path());
  headers.emplace_back("outcome");
  headers.emplace_back("detail");
  std::vector<std::vector<HtmlCell>> rows;
  for (std::size_t i = 0; i < failing.size() && i < kSweepPageMaxFailing; ++i) {
    const proto::SweepCaseResult& row = *failing[i];
    std::vector<HtmlCell> cells = {CaseCell(row), TextCell(row.scenario()),
                                   NumberCell(static_cast<double>(row.seed()))};
    for (int a = 0; a < sweep.spec.axis_size(); ++a) {
      cells.push_back(a < row.value_size() ? NumberCell(row.value(a)) : TextCell("-"));
    }
    cells.push_back(TextCell(OutcomeName(row.outcome()), Tone::kFail));
    cells.push_back(TextCell(row.detail()));
    rows.push_back(std::move(cells));
    // The command on a row of its own under the case, as wide as the table.
    rows.push_back(
        {{"<code>" + HtmlText(ReproduceCommand(sweep, row, hilrig, runs_dir)) + "</code>",
          Tone::kPlain, false, static_cast<int>(headers.size())}});
  }
  html += "<p>" + std::to_string(failing.size()) + " of " + std::to_string(results.size()) +
          " cases, each followed by the command that runs it alone (as in failing.txt); the case "
          "number links to its run folder's page.</p>\n" +
          HtmlTable(headers, rows);
  if (failing.size() > kSweepPageMaxFailing) {
    html += "<p>The first " + std::to_string(kSweepPageMaxFailing) + " shown; " +
            std::to_string(failing.size() - kSweepPageMaxFailing) +
            " more in <a href=\"failing.txt\">failing.txt</a>.</p>\n";
  }
  return html;
}

}  // namespace

std::string SweepPageHtml(const LoadedSweep& sweep,
                          const std::vector<proto::SweepCaseResult>& results,
                          const proto::SweepSummary& summary, const std::string& hilrig,
                          const std::string& runs_dir) {
  std::vector<std::string> files = {"summary.json", "runs.csv", "failing.txt", "sweep.textproto"};
  if (SweepMapAxes(sweep.spec)) files.emplace_back(kSweepMapFile);
  const std::string body = Heading(sweep, results, summary) + CriteriaSection(sweep, summary) +
                           EnvelopeSection(sweep, summary) + MapSection(sweep, results) +
                           HistogramSection(sweep, results, summary) +
                           FailingSection(sweep, results, hilrig, runs_dir) + HtmlFileLinks(files);
  return HtmlDocument("Sweep " + sweep.spec.name() + ": " + SweepVerdict(summary).word, body);
}

}  // namespace hilrig::host
