#include "host/report/accuracy_page.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "host/report/html_page.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

void SetAxes(proto::Vector3* v, double x, double y, double z) {
  v->set_x(x);
  v->set_y(y);
  v->set_z(z);
}

proto::ConditionAccuracy Condition(const std::string& name, double max_z_n) {
  proto::ConditionAccuracy condition;
  condition.set_condition(name);
  SetAxes(condition.mutable_rmse_n(), 0.0024, 0.0030, 0.0062);
  SetAxes(condition.mutable_p95_n(), 0.0047, 0.0057, 0.0119);
  SetAxes(condition.mutable_max_n(), 0.0086, 0.0112, max_z_n);
  condition.set_samples(2400);
  condition.set_flagged(3);
  return condition;
}

// As `hilrig accuracy` writes it: the compensated condition first, then the uncompensated one.
proto::AccuracyReport Report(double compensated_max_z_n) {
  proto::AccuracyReport report;
  *report.add_conditions() = Condition(kCompensatedCondition, compensated_max_z_n);
  *report.add_conditions() = Condition("uncompensated", 0.522);
  report.set_attitudes(100);
  report.set_loads_per_attitude(4);
  report.set_sensors(6);
  report.set_field_fidelity("map:16");
  report.set_seed(1001);
  report.set_dut_filter_samples(3);
  return report;
}

TEST(AccuracyPageTest, ACompensatedMaximumWithinTheTargetOnEveryAxisPasses) {
  const std::string html = AccuracyPageHtml(Report(0.0162));
  EXPECT_THAT(html, HasSubstr(HtmlBadge("within 0.02 N", Tone::kPass)));
  EXPECT_THAT(html, Not(HasSubstr("above 0.02 N")));
  EXPECT_THAT(html, HasSubstr("<title>Held-out force accuracy: within 0.02 N</title>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"pass num\">0.0162</td>"));
}

TEST(AccuracyPageTest, ACompensatedMaximumAboveTheTargetFails) {
  const std::string html = AccuracyPageHtml(Report(0.0249));
  EXPECT_THAT(html, HasSubstr(HtmlBadge("above 0.02 N", Tone::kFail)));
  EXPECT_THAT(html, Not(HasSubstr("within 0.02 N")));
  EXPECT_THAT(html, HasSubstr("<td class=\"fail num\">0.0249</td>"));
  // The uncompensated condition is not graded: its maximum is plain.
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">0.522</td>"));
}

TEST(AccuracyPageTest, ANonFiniteMaximumIsNotWithinTheTarget) {
  const std::string html = AccuracyPageHtml(Report(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_THAT(html, HasSubstr(HtmlBadge("above 0.02 N", Tone::kFail)));
  EXPECT_THAT(html, Not(HasSubstr("=\"nan\"")));  // the chart marks it n/a, no NaN pixel
  EXPECT_THAT(html, HasSubstr(">n/a</text>"));
}

TEST(AccuracyPageTest, WithoutACompensatedConditionTheBadgeIsNeutral) {
  proto::AccuracyReport report = Report(0.0162);
  report.mutable_conditions(0)->set_condition("something else");
  EXPECT_THAT(AccuracyPageHtml(report),
              HasSubstr(HtmlBadge("no compensated condition", Tone::kNeutral)));
}

TEST(AccuracyPageTest, ShowsTheConditionsTheSetUpAndTheChart) {
  const std::string html = AccuracyPageHtml(Report(0.0162));
  for (const char* header : {"RMSE x (N)", "p95 y (N)", "max z (N)", "samples", "flagged"}) {
    EXPECT_THAT(html, HasSubstr(std::string("<th>") + header + "</th>")) << header;
  }
  EXPECT_THAT(html, HasSubstr("<td>uncompensated</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">0.0119</td>"));  // p95 z
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">2400</td>"));
  EXPECT_THAT(html, HasSubstr("<td>field fidelity</td><td>map:16</td>"));
  EXPECT_THAT(html, HasSubstr("<td>seed (held-out)</td><td class=\"num\">1001</td>"));
  EXPECT_THAT(html, HasSubstr("<td>DUT filter samples</td><td class=\"num\">3</td>"));
  EXPECT_THAT(html, HasSubstr("6 sensors x 100 attitudes x 4 held-out loads per attitude"));
  // The chart: max and RMSE rows per condition, and the target line in the legend.
  EXPECT_THAT(html, HasSubstr("<svg"));
  EXPECT_THAT(html, Not(HasSubstr("<?xml")));
  EXPECT_THAT(html, HasSubstr(">compensated max</text>"));
  EXPECT_THAT(html, HasSubstr(">uncompensated RMSE</text>"));
  EXPECT_THAT(html, HasSubstr(">0.02 N held-out target</text>"));
  EXPECT_THAT(html, HasSubstr("href=\"accuracy.json\""));
}

TEST(AccuracyPageTest, NamesAreEscaped) {
  proto::AccuracyReport report = Report(0.0162);
  report.mutable_conditions(1)->set_condition("<&>");
  report.set_field_fidelity("a<b");
  const std::string html = AccuracyPageHtml(report);
  EXPECT_THAT(html, HasSubstr("<td>&lt;&amp;&gt;</td>"));
  EXPECT_THAT(html, HasSubstr(">&lt;&amp;&gt; max</text>"));
  EXPECT_THAT(html, HasSubstr("a&lt;b"));
  EXPECT_THAT(html, Not(HasSubstr("<&>")));
}

TEST(AccuracyPageTest, AnEmptyReportGivesAPage) {
  const std::string html = AccuracyPageHtml(proto::AccuracyReport());
  EXPECT_THAT(html, HasSubstr("<!DOCTYPE html>"));
  EXPECT_THAT(html, HasSubstr(HtmlBadge("no compensated condition", Tone::kNeutral)));
  EXPECT_THAT(html, HasSubstr("No condition was measured"));
  EXPECT_THAT(html, HasSubstr("</html>"));
}

TEST(AccuracyPageTest, SameReportSameBytes) {
  EXPECT_EQ(AccuracyPageHtml(Report(0.0162)), AccuracyPageHtml(Report(0.0162)));
  EXPECT_EQ(BudgetPageHtml(proto::AccuracyBudget()), BudgetPageHtml(proto::AccuracyBudget()));
}

proto::AccuracyBudget Budget() {
  proto::AccuracyBudget budget;
  const auto add = [&](const std::string& configuration, std::vector<std::string> effects,
                       double max_z_n) {
    proto::BudgetRow* row = budget.add_rows();
    row->set_configuration(configuration);
    for (const std::string& effect : effects) row->add_effects_on(effect);
    *row->mutable_compensated() = Condition(kCompensatedCondition, max_z_n);
  };
  add(kFloorConfiguration, {}, 0.0094);
  add("only chip_noise", {"chip_noise"}, 0.0240);
  add("all but chip_noise", {"earth_field", "silicone_damping"}, 0.0108);
  add("all", {"chip_noise", "earth_field", "silicone_damping"}, 0.0249);
  add("all + silicone_stiffening", {"chip_noise", "silicone_stiffening"}, 0.0363);
  SetAxes(budget.mutable_floor_rmse_n(), 0.0015, 0.0016, 0.0031);
  SetAxes(budget.mutable_combined_rmse_n(), 0.0024, 0.0030, 0.0066);
  SetAxes(budget.mutable_total_rmse_n(), 0.0024, 0.0030, 0.0062);
  SetAxes(budget.mutable_gap_rmse_n(), -0.00001, -0.00002, -0.0004);
  *budget.mutable_decoding_floor() = Condition("decoder", 0.0097);
  budget.set_field_fidelity("tiles:32");
  budget.set_seed(1);
  return budget;
}

TEST(BudgetPageTest, ShowsEveryRowInTheTableAndTheChartInFileOrder) {
  const proto::AccuracyBudget budget = Budget();
  const std::string html = BudgetPageHtml(budget);
  std::size_t last_label = 0;
  for (const proto::BudgetRow& row : budget.rows()) {
    EXPECT_THAT(html, HasSubstr("<tr><td>" + row.configuration() + "</td>"));
    const std::size_t label = html.find(">" + row.configuration() + "</text>");
    ASSERT_NE(label, std::string::npos) << row.configuration();
    EXPECT_GT(label, last_label) << row.configuration();
    last_label = label;
  }
  EXPECT_THAT(html, HasSubstr("<td>none</td><td>none</td>"));  // the floor has no effect on
  EXPECT_THAT(html, HasSubstr("<td>earth_field, silicone_damping</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">0.0363</td>"));
  EXPECT_THAT(html, HasSubstr("<svg"));
  EXPECT_THAT(html, HasSubstr(">floor (none) z max 0.0094 N</text>"));
  EXPECT_THAT(html, HasSubstr(">0.02 N held-out target</text>"));
  EXPECT_THAT(html, HasSubstr("href=\"budget.json\""));
}

TEST(BudgetPageTest, ShowsTheFloorTheCombinationTheTotalTheGapAndTheDecoderAlone) {
  const std::string html = BudgetPageHtml(Budget());
  EXPECT_THAT(html, HasSubstr("<td>decoder alone (exact field)</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">0.0097</td>"));  // the decoder's max z
  EXPECT_THAT(html, HasSubstr("<td>floor (none)</td><td class=\"num\">0.0015</td>"));
  EXPECT_THAT(html, HasSubstr("<td>floor + effects alone (RSS)</td><td class=\"num\">0.0024</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">0.0066</td>"));
  EXPECT_THAT(html, HasSubstr("<td>measured total (all)</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"num\">-0.0004</td>"));
  EXPECT_THAT(html, HasSubstr("field tiles:32; seed 1"));
}

TEST(BudgetPageTest, WithoutAFloorRowOnlyTheTargetIsDrawn) {
  proto::AccuracyBudget budget = Budget();
  budget.mutable_rows()->erase(budget.mutable_rows()->begin());
  const std::string html = BudgetPageHtml(budget);
  EXPECT_THAT(html, Not(HasSubstr("z max")));
  EXPECT_THAT(html, HasSubstr(">0.02 N held-out target</text>"));
}

TEST(BudgetPageTest, AnEmptyBudgetGivesAPage) {
  const std::string html = BudgetPageHtml(proto::AccuracyBudget());
  EXPECT_THAT(html, HasSubstr("<!DOCTYPE html>"));
  EXPECT_THAT(html, HasSubstr("No configuration was measured"));
  EXPECT_THAT(html, HasSubstr("<td>floor (none)</td>"));
  EXPECT_THAT(html, HasSubstr("</html>"));
}

}  // namespace
}  // namespace hilrig::host
