#include "host/report/accuracy_page.h"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "host/report/bar_plot.h"
#include "host/report/html_page.h"

namespace hilrig::host {
namespace {

// The page's fail colour (html_page.cc) for the target line, so it reads as the limit.
constexpr const char* kTargetColor = "#CF222E";
constexpr std::array<const char*, 3> kAxes = {"x", "y", "z"};

std::array<double, 3> AxesOf(const proto::Vector3& v) { return {v.x(), v.y(), v.z()}; }

// "RMSE x (N)", "RMSE y (N)", "RMSE z (N)".
std::vector<std::string> AxisHeaders(const std::string& figure) {
  std::vector<std::string> headers;
  for (const char* axis : kAxes) headers.push_back(figure + " " + axis + " (N)");
  return headers;
}

void Append(std::vector<std::string>& to, const std::vector<std::string>& more) {
  to.insert(to.end(), more.begin(), more.end());
}

void AppendAxisCells(std::vector<HtmlCell>& row, const proto::Vector3& v) {
  for (const double value : AxesOf(v)) row.push_back(NumberCell(value));
}

bool WithinTarget(double max_n) { return max_n <= kHeldOutTargetN; }  // NaN is not within

bool WithinTarget(const proto::Vector3& max_n) {
  for (const double value : AxesOf(max_n)) {
    if (!WithinTarget(value)) return false;
  }
  return true;
}

std::string TargetText() { return PageNumber(kHeldOutTargetN) + " N"; }

BarReference TargetLine() {
  return {TargetText() + " held-out target", kHeldOutTargetN, kTargetColor};
}

// One series per axis, colours from kSeriesPalette.
std::vector<BarSeries> AxisSeries() {
  std::vector<BarSeries> series;
  for (const char* axis : kAxes) series.push_back({axis, "", {}});
  return series;
}

void AppendAxisValues(std::vector<BarSeries>& series, const proto::Vector3& v) {
  const std::array<double, 3> values = AxesOf(v);
  for (std::size_t axis = 0; axis < values.size(); ++axis) {
    series[axis].values.push_back(values[axis]);
  }
}

std::string Figure(const BarPlot& plot, const std::string& id_prefix) {
  return "<figure>\n" + InlineSvg(RenderBarSvg(plot), id_prefix) + "</figure>\n";
}

// ---------------------------------------------------------------------------------------------
// The accuracy page.

const proto::ConditionAccuracy* CompensatedOf(const proto::AccuracyReport& report) {
  for (const proto::ConditionAccuracy& condition : report.conditions()) {
    if (condition.condition() == kCompensatedCondition) return &condition;
  }
  return nullptr;
}

// The badge's word and colour; the word names the target, so it is built, not a fixed string.
struct Grade {
  std::string word;
  Tone tone = Tone::kNeutral;
};

Grade GradeOf(const proto::AccuracyReport& report) {
  const proto::ConditionAccuracy* compensated = CompensatedOf(report);
  if (compensated == nullptr) return {"no compensated condition", Tone::kNeutral};
  if (WithinTarget(compensated->max_n())) return {"within " + TargetText(), Tone::kPass};
  return {"above " + TargetText(), Tone::kFail};
}

std::string SetUpLine(const proto::AccuracyReport& report) {
  return std::to_string(report.sensors()) + " sensors x " + std::to_string(report.attitudes()) +
         " attitudes x " + std::to_string(report.loads_per_attitude()) +
         " held-out loads per attitude; field " + report.field_fidelity() + "; DUT filter " +
         std::to_string(report.dut_filter_samples()) + " sample(s)";
}

// A count or a seed, every digit: PageNumber would round a 64-bit seed to four.
HtmlCell WholeCell(std::uint64_t value) { return {std::to_string(value), Tone::kPlain, true, 1}; }

std::string ConditionsTable(const proto::AccuracyReport& report) {
  std::vector<std::string> headers = {"condition"};
  Append(headers, AxisHeaders("RMSE"));
  Append(headers, AxisHeaders("p95"));
  Append(headers, AxisHeaders("max"));
  Append(headers, {"samples", "flagged"});
  std::vector<std::vector<HtmlCell>> rows;
  for (const proto::ConditionAccuracy& condition : report.conditions()) {
    std::vector<HtmlCell> row = {TextCell(condition.condition())};
    AppendAxisCells(row, condition.rmse_n());
    AppendAxisCells(row, condition.p95_n());
    // The compensated maxima are what the target grades: each in its verdict's colour.
    const bool graded = condition.condition() == kCompensatedCondition;
    for (const double value : AxesOf(condition.max_n())) {
      HtmlCell cell = NumberCell(value);
      if (graded) cell.tone = WithinTarget(value) ? Tone::kPass : Tone::kFail;
      row.push_back(cell);
    }
    row.push_back(WholeCell(condition.samples()));
    row.push_back(WholeCell(condition.flagged()));
    rows.push_back(std::move(row));
  }
  return HtmlTable(headers, rows);
}

std::string SetUpTable(const proto::AccuracyReport& report) {
  return HtmlTable(
      {"set-up", "value"},
      {{TextCell("attitudes"), WholeCell(report.attitudes())},
       {TextCell("held-out loads per attitude"), WholeCell(report.loads_per_attitude())},
       {TextCell("sensors"), WholeCell(report.sensors())},
       {TextCell("field fidelity"), TextCell(report.field_fidelity())},
       {TextCell("seed (held-out)"), WholeCell(report.seed())},
       {TextCell("DUT filter samples"), WholeCell(report.dut_filter_samples())}});
}

BarPlot AccuracyPlot(const proto::AccuracyReport& report) {
  BarPlot plot;
  plot.title = "Held-out force error per axis";
  plot.x_label = "error (N)";
  plot.series = AxisSeries();
  for (const proto::ConditionAccuracy& condition : report.conditions()) {
    plot.categories.push_back(condition.condition() + " max");
    AppendAxisValues(plot.series, condition.max_n());
    plot.categories.push_back(condition.condition() + " RMSE");
    AppendAxisValues(plot.series, condition.rmse_n());
  }
  plot.references = {TargetLine()};
  return plot;
}

// ---------------------------------------------------------------------------------------------
// The budget page.

std::string EffectsText(const proto::BudgetRow& row) {
  std::string text;
  for (const std::string& effect : row.effects_on()) text += (text.empty() ? "" : ", ") + effect;
  return text.empty() ? "none" : text;
}

std::string BudgetTable(const proto::AccuracyBudget& budget) {
  std::vector<std::string> headers = {"configuration", "effects on"};
  Append(headers, AxisHeaders("RMSE"));
  Append(headers, AxisHeaders("max"));
  std::vector<std::vector<HtmlCell>> rows;
  for (const proto::BudgetRow& row : budget.rows()) {
    std::vector<HtmlCell> cells = {TextCell(row.configuration()), TextCell(EffectsText(row))};
    AppendAxisCells(cells, row.compensated().rmse_n());
    AppendAxisCells(cells, row.compensated().max_n());
    rows.push_back(std::move(cells));
  }
  return HtmlTable(headers, rows);
}

// The decoder alone, then the floor, the root sum of squares of the floor and the effects alone,
// the measured total and the gap between them, worded as `hilrig accuracy --budget` prints them.
std::string CombinationTable(const proto::AccuracyBudget& budget) {
  std::vector<std::string> headers = {"figure"};
  Append(headers, AxisHeaders("RMSE"));
  Append(headers, AxisHeaders("max"));
  std::vector<HtmlCell> decoder = {TextCell("decoder alone (exact field)")};
  AppendAxisCells(decoder, budget.decoding_floor().rmse_n());
  AppendAxisCells(decoder, budget.decoding_floor().max_n());
  std::vector<std::vector<HtmlCell>> rows = {std::move(decoder)};
  const std::pair<const char*, const proto::Vector3*> lines[] = {
      {"floor (none)", &budget.floor_rmse_n()},
      {"floor + effects alone (RSS)", &budget.combined_rmse_n()},
      {"measured total (all)", &budget.total_rmse_n()},
      {"gap (together beyond alone)", &budget.gap_rmse_n()}};
  for (const auto& [name, rmse_n] : lines) {
    std::vector<HtmlCell> row = {TextCell(name)};
    AppendAxisCells(row, *rmse_n);
    rows.push_back(std::move(row));
  }
  return HtmlTable(headers, rows);
}

const proto::BudgetRow* FloorRowOf(const proto::AccuracyBudget& budget) {
  for (const proto::BudgetRow& row : budget.rows()) {
    if (row.configuration() == kFloorConfiguration) return &row;
  }
  return nullptr;
}

BarPlot BudgetPlot(const proto::AccuracyBudget& budget) {
  BarPlot plot;
  plot.title = "Held-out maximum force error per configuration";
  plot.x_label = "max error (N)";
  plot.series = AxisSeries();
  for (const proto::BudgetRow& row : budget.rows()) {
    plot.categories.push_back(row.configuration());
    AppendAxisValues(plot.series, row.compensated().max_n());
  }
  if (const proto::BudgetRow* floor = FloorRowOf(budget)) {
    const double z_max_n = floor->compensated().max_n().z();
    plot.references.push_back(
        {"floor (" + std::string(kFloorConfiguration) + ") z max " + PageNumber(z_max_n) + " N",
         z_max_n, ""});
  }
  plot.references.push_back(TargetLine());
  return plot;
}

}  // namespace

std::string AccuracyPageHtml(const proto::AccuracyReport& report) {
  const Grade grade = GradeOf(report);
  std::string body = "<h1>Held-out force accuracy " + HtmlBadge(grade.word, grade.tone) +
                     "</h1>\n<p class=\"sub\">" + HtmlText(SetUpLine(report)) + "</p>\n";
  body +=
      "<p>The force error of decoding loads the calibration never saw, over an attitude sweep, "
      "per condition and sensor axis. The badge grades the " +
      HtmlText(kCompensatedCondition) + " condition's maximum against the " +
      HtmlText(TargetText()) + " held-out target on every axis.</p>\n";
  body += "<h2>Conditions</h2>\n";
  if (report.conditions().empty()) {
    body += "<p>No condition was measured: nothing to show.</p>\n";
  } else {
    body += ConditionsTable(report) + Figure(AccuracyPlot(report), "accuracy-");
  }
  body += "<h2>Set-up</h2>\n" + SetUpTable(report) + HtmlFileLinks({kAccuracyJsonFile});
  return HtmlDocument("Held-out force accuracy: " + grade.word, body);
}

std::string BudgetPageHtml(const proto::AccuracyBudget& budget) {
  std::string body = "<h1>Force-error budget</h1>\n<p class=\"sub\">" +
                     std::to_string(budget.rows_size()) + " configurations; field " +
                     HtmlText(budget.field_fidelity()) + "; seed " + std::to_string(budget.seed()) +
                     "; DUT filter " + std::to_string(budget.dut_filter_samples()) +
                     " sample(s)</p>\n";
  body +=
      "<p>Which effects of the forward model make the held-out error what it is: each row is "
      "the bench with only the named effects on, calibrated as a lab would and measured on "
      "held-out loads, compensated. The \"" +
      HtmlText(kFloorConfiguration) +
      "\" row is the decoding model's own floor; each effect's contribution is "
      "sqrt(rmse_only&sup2; &minus; rmse_floor&sup2;) per axis.</p>\n";
  body += "<h2>Configurations</h2>\n";
  if (budget.rows().empty()) {
    body += "<p>No configuration was measured: nothing to show.</p>\n";
  } else {
    body += BudgetTable(budget) + Figure(BudgetPlot(budget), "budget-");
  }
  body += "<h2>Floor, effects and total</h2>\n" + CombinationTable(budget) +
          HtmlFileLinks({kBudgetJsonFile});
  return HtmlDocument("Force-error budget", body);
}

}  // namespace hilrig::host
