#include "host/report/run_page.h"

#include <filesystem>

#include "host/report/html_page.h"
#include "host/report/report_files.h"
#include "host/report/signal_unit.h"
#include "host/report/stop_reason.h"
#include "rig/file_io.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// A plot is a few hundred kilobytes at most (svg_plot.h decimates long series); anything larger is
// not the rig's plot.
constexpr std::size_t kMaxPlotBytes = 16u << 20;

PageVerdict RunVerdict(const proto::Report& report) {
  if (report.stop_kind() == proto::STOP_INCOMPLETE) return {"INCOMPLETE", Tone::kNeutral};
  return report.passed() ? PageVerdict{"PASS", Tone::kPass} : PageVerdict{"FAIL", Tone::kFail};
}

Tone VerdictTone(proto::Verdict verdict) {
  return verdict == proto::PASS ? Tone::kPass : Tone::kFail;
}

const char* VerdictWord(proto::Verdict verdict) { return verdict == proto::PASS ? "PASS" : "FAIL"; }

// A duration on the page: PageNumber's digits and " s".
std::string PageSeconds(double value) { return PageNumber(value) + " s"; }

std::string Heading(const proto::Report& report) {
  const PageVerdict verdict = RunVerdict(report);
  std::string html = "<h1>" + HtmlText(report.scenario()) + " " +
                     HtmlBadge(verdict.word, verdict.tone) + "</h1>\n<p class=\"sub\">";
  if (!report.spec_file().empty()) html += HtmlText(report.spec_file()) + " &middot; ";
  html += "seed " + std::to_string(report.seed()) + " &middot; " + HtmlText(report.stop_reason()) +
          " at " + HtmlText(PageSeconds(report.simulated_s())) + " simulated</p>\n";
  return html;
}

// The run's figures: how it stopped, its times and speed, what it counted on the bus.
std::string RunTable(const proto::Report& report) {
  const bool stopped_early = !RunCompleted(report);
  std::vector<std::vector<HtmlCell>> rows = {
      {TextCell("stop reason"),
       TextCell(report.stop_reason(), stopped_early ? Tone::kFail : Tone::kPlain)},
      {TextCell("simulated time"), NumberCell(report.simulated_s(), "s")},
      {TextCell("wall time (stepping loop)"), NumberCell(report.wall_s(), "s")},
      {TextCell("real-time factor"),
       {HtmlText(rig::FactorText(report.real_time_factor())), Tone::kPlain, true, 1}},
      {TextCell("set-up time"), NumberCell(report.setup_s(), "s")},
      {TextCell("ticks"), NumberCell(static_cast<double>(report.ticks()))},
      {TextCell("CAN frames logged"), NumberCell(static_cast<double>(report.can_frames_logged()))},
  };
  if (!report.timing().mode().empty()) {
    rows.push_back({TextCell("timing"), TextCell(report.timing().mode())});
  }
  if (report.has_dut_faults()) {
    rows.push_back(
        {TextCell("DUT fault"), TextCell(FormatDutFaultLine(report.dut_faults()), Tone::kFail)});
  }
  return "<h2>Run</h2>\n" + HtmlTable({"figure", "value"}, rows);
}

std::string LimitText(const proto::EnvelopeResult& result, const std::string& unit) {
  std::string text = "[";
  text += result.has_lower() ? rig::NumberText(result.lower()) : "-";
  text += ", ";
  text += result.has_upper() ? rig::NumberText(result.upper()) : "-";
  text += "]";
  if (!unit.empty()) text += " " + unit;
  return text;
}

// The expected verdict: plain when the default (PASS) was met, green when an expected FAIL was met,
// red when not met.
HtmlCell ExpectedCell(const proto::EnvelopeResult& result) {
  const std::string expected = VerdictWord(result.expected());
  if (!result.meets_expectation()) return TextCell(expected + ", NOT MET", Tone::kFail);
  if (result.expected() == proto::PASS) return TextCell(expected);
  return TextCell(expected + ", met", Tone::kPass);
}

std::string EnvelopeTable(const proto::Report& report) {
  if (report.envelopes_size() == 0) return "<h2>Envelopes</h2>\n<p>The spec has no envelope.</p>\n";
  std::vector<std::vector<HtmlCell>> rows;
  for (const proto::EnvelopeResult& result : report.envelopes()) {
    const std::string unit = SignalUnit(result.signal());
    std::vector<HtmlCell> row = {
        result.not_evaluated()
            ? TextCell("NOT EVALUATED", Tone::kFail)
            : TextCell(VerdictWord(result.verdict()), VerdictTone(result.verdict())),
        TextCell(result.name()), TextCell(proto::Signal_Name(result.signal()))};
    if (result.samples_checked() == 0) {
      row.push_back(TextCell("no samples in its window"));
      row.push_back(TextCell("-"));
    } else {
      row.push_back(NumberCell(result.worst_value(), unit));
      row.push_back(NumberCell(result.worst_at_s(), "s"));
    }
    row.push_back({HtmlText(LimitText(result, unit)), Tone::kPlain, true, 1});
    row.push_back(result.samples_checked() == 0 ? TextCell("-")
                                                : NumberCell(result.margin(), unit));
    row.push_back(result.verdict() == proto::FAIL && result.samples_checked() > 0
                      ? NumberCell(result.first_violation_at_s(), "s")
                      : TextCell("-"));
    row.push_back(ExpectedCell(result));
    rows.push_back(std::move(row));
  }
  return "<h2>Envelopes</h2>\n" + HtmlTable({"verdict", "envelope", "signal", "worst", "at",
                                             "limits", "margin", "first out at", "expected"},
                                            rows);
}

// The timing or target checks, `kind` naming them ("timing", "target").
std::string CheckTable(const google::protobuf::RepeatedPtrField<proto::TimingCheckResult>& checks,
                       const std::string& kind) {
  std::vector<std::vector<HtmlCell>> rows;
  for (const proto::TimingCheckResult& check : checks) {
    rows.push_back({!check.evaluated() ? TextCell("----", Tone::kNeutral)
                    : check.passed()   ? TextCell("PASS", Tone::kPass)
                                       : TextCell("FAIL", Tone::kFail),
                    TextCell(check.name()),
                    check.evaluated() ? TextCell(FormatTimingValue(check.value(), check.unit()))
                                      : TextCell("-"),
                    TextCell(FormatTimingValue(check.limit(), check.unit())),
                    TextCell(check.note())});
  }
  return HtmlTable({"verdict", kind + " check", "value", "limit", "note"}, rows);
}

std::string ChecksSection(const proto::Report& report) {
  if (report.timing_checks_size() == 0 && report.target_checks_size() == 0) return "";
  std::string html = "<h2>Timing and target</h2>\n";
  if (report.timing_checks_size() > 0) html += CheckTable(report.timing_checks(), "timing");
  if (report.target_checks_size() > 0) html += CheckTable(report.target_checks(), "target");
  for (const std::string& line : FormatRealtimeTiming(report.timing())) {
    html += "<p>" + HtmlText(line) + "</p>\n";
  }
  if (report.has_target()) html += "<p>" + HtmlText(FormatTargetLine(report.target())) + "</p>\n";
  return html;
}

std::string ObjectTable(const proto::Report& report) {
  if (report.objects_size() == 0) return "";
  std::vector<std::vector<HtmlCell>> rows;
  for (const proto::ObjectOutcome& object : report.objects()) {
    const bool damaged = object.damage() != "none";
    rows.push_back(
        {TextCell(object.fixture()), TextCell(object.damage(), damaged ? Tone::kFail : Tone::kPass),
         damaged ? NumberCell(object.damaged_at_s(), "s") : TextCell("-"),
         TextCell(object.final_state()), NumberCell(object.peak_normal_force_n(), "N"),
         object.has_damage_force_n() ? NumberCell(object.damage_force_n(), "N") : TextCell("-"),
         object.has_damage_margin_n()
             ? HtmlCell{NumberCell(object.damage_margin_n(), "N").html,
                        object.damage_margin_n() > 0 ? Tone::kPass : Tone::kFail, true}
             : TextCell("-"),
         NumberCell(object.peak_indentation_m(), "m")});
  }
  return "<h2>Objects</h2>\n" +
         HtmlTable({"object", "damage", "at", "final state", "peak force per pad", "damaged at",
                    "margin", "peak indentation"},
                   rows);
}

std::string FidelitySection(const proto::Report& report) {
  if (!report.has_fidelity_error()) return "";
  const proto::FidelityError& error = report.fidelity_error();
  const bool grasp = report.objects_size() > 0;
  std::vector<std::vector<HtmlCell>> rows;
  if (grasp) {
    rows.push_back({TextCell("grasp force"), NumberCell(error.grasp_force_rms_n(), "N"),
                    NumberCell(error.grasp_force_max_n(), "N")});
    rows.push_back({TextCell("load"), NumberCell(error.load_rms_n(), "N"),
                    NumberCell(error.load_max_n(), "N")});
  }
  rows.push_back({TextCell("position"), NumberCell(error.position_rms_m(), "m"),
                  NumberCell(error.position_max_m(), "m")});
  return "<h2>Fidelity error</h2>\n<p>Against the reference " +
         HtmlText(error.reference_fidelity()) + (error.reference_cached() ? " (cached)" : "") +
         ", " + std::to_string(error.samples_compared()) + " samples compared.</p>\n" +
         HtmlTable({"signal", "RMS", "max"}, rows);
}

std::string PlotSection(const std::vector<RunPagePlot>& plots) {
  if (plots.empty()) return "";
  std::string html = "<h2>Plots</h2>\n";
  int index = 0;
  for (const RunPagePlot& plot : plots) {
    html += "<figure>\n";
    if (plot.svg.empty()) {
      html += "<p>" + HtmlText(plot.file) + " could not be read.</p>\n";
    } else {
      html += InlineSvg(plot.svg, "plot" + std::to_string(index++) + "-");
    }
    html += "<figcaption><a href=\"" + HtmlText(plot.file) + "\">" + HtmlText(plot.file) +
            "</a></figcaption>\n</figure>\n";
  }
  return html;
}

// The counters (DUT messages, CAN frames, samples lost) first, then every other metric folded.
std::string MetricSection(const proto::Report& report) {
  if (report.metrics_size() == 0) return "";
  std::vector<std::vector<HtmlCell>> counts, others;
  for (const proto::Metric& metric : report.metrics()) {
    const bool count = metric.unit() == "count";
    (count ? counts : others)
        .push_back(
            {TextCell(metric.name()), NumberCell(metric.value(), count ? "" : metric.unit())});
  }
  std::string html = "<h2>Metrics</h2>\n";
  if (!counts.empty()) html += "<h3>Counters</h3>\n" + HtmlTable({"counter", "value"}, counts);
  if (!others.empty()) {
    html += "<details><summary>" + std::to_string(others.size()) + " more metrics</summary>\n" +
            HtmlTable({"metric", "value"}, others) + "</details>\n";
  }
  return html;
}

std::string ModelSection(const proto::Report& report) {
  if (report.models_size() == 0) return "";
  std::vector<std::vector<HtmlCell>> rows;
  for (const proto::ModelInfo& model : report.models()) {
    rows.push_back({TextCell(model.name()), TextCell(model.fidelity())});
  }
  return "<details><summary>Models (" + std::to_string(rows.size()) + ")</summary>\n" +
         HtmlTable({"model", "fidelity"}, rows) + "</details>\n";
}

// What made the run: the rig's build, the command and the numbers --set changed in the spec.
std::string ProvenanceSection(const proto::Report& report) {
  if (!report.has_provenance()) return "";
  const proto::Provenance& made = report.provenance();
  std::vector<std::vector<HtmlCell>> rows = {
      {TextCell("rig commit"), TextCell(made.rig_commit())},
      {TextCell("build type"), TextCell(made.build_type())},
      {TextCell("command"), {"<code>" + HtmlText(made.command_line()) + "</code>"}}};
  for (const proto::SpecOverride& set : made.overrides()) {
    rows.push_back({TextCell("--set " + set.path()), NumberCell(set.value())});
  }
  return "<h2>Made by</h2>\n" + HtmlTable({"what", "value"}, rows);
}

}  // namespace

std::string RunPageHtml(const proto::Report& report, const std::vector<RunPagePlot>& plots) {
  const std::string body = Heading(report) + EnvelopeTable(report) + ObjectTable(report) +
                           RunTable(report) + FidelitySection(report) + PlotSection(plots) +
                           ChecksSection(report) + MetricSection(report) + ModelSection(report) +
                           ProvenanceSection(report) +
                           HtmlFileLinks({"report.json", "junit.xml", "trace.csv", "can.log"});
  return HtmlDocument(report.scenario() + ": " + RunVerdict(report).word, body);
}

rig::Result<void> WriteRunPage(const proto::Report& report, const std::string& out_dir) {
  const std::filesystem::path folder(out_dir);
  std::vector<RunPagePlot> plots;
  for (const std::string& file : report.plots()) {
    auto svg = rig::ReadRegularFile((folder / file).string(), kMaxPlotBytes);
    plots.push_back({file, svg ? std::move(svg).value() : std::string()});
  }
  return WriteTextFile((folder / kRunPageFile).string(), RunPageHtml(report, plots));
}

}  // namespace hilrig::host
