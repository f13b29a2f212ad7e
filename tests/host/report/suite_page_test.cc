// The page of a folder run: one row per scenario file, linked to its run page, and a verdict that
// is INCOMPLETE until every file has run.
#include "host/report/suite_page.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

SuiteRow Ran(const std::string& name, SuiteVerdict verdict) {
  SuiteRow row;
  row.name = name;
  row.verdict = verdict;
  row.envelopes_met = verdict == SuiteVerdict::kPass ? 3 : 2;
  row.envelopes = 3;
  row.real_time_factor = 1174.4;
  row.stop_reason = "completed";
  row.has_page = true;
  return row;
}

TEST(SuitePageTest, ListsEachScenarioLinkedToItsRunPage) {
  const std::string html = SuitePageHtml(
      "scenarios/", {Ran("balloon_grasp", SuiteVerdict::kPass), Ran("hover", SuiteVerdict::kPass)},
      2);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_THAT(html, HasSubstr("<title>Scenarios in scenarios/: PASS</title>"));
  EXPECT_THAT(html, HasSubstr("<span class=\"badge pass\">PASS</span>"));
  EXPECT_THAT(html, HasSubstr("2 of 2 scenario files run, 2 passed"));
  EXPECT_THAT(html, HasSubstr("<tr><td><a href=\"balloon_grasp/index.html\">balloon_grasp</a></td>"
                              "<td class=\"pass\">PASS</td><td class=\"num\">3 / 3</td>"
                              "<td class=\"num\">1174x</td><td>completed</td></tr>"));
  EXPECT_THAT(html, Not(HasSubstr("did not run")));
  EXPECT_THAT(html, Not(HasSubstr("<script")));
}

TEST(SuitePageTest, AFailingOrInvalidFileFailsThePageAndSaysWhyItDidNotRun) {
  SuiteRow invalid;
  invalid.name = "broken <spec>";
  invalid.error = "broken.textproto:2:1: simulation.duration_s: must be positive";
  const std::string html = SuitePageHtml(
      "s", {Ran("a", SuiteVerdict::kFail), Ran("b", SuiteVerdict::kPass), invalid}, 3);
  EXPECT_THAT(html, HasSubstr("<span class=\"badge fail\">FAIL</span>"));
  EXPECT_THAT(html, HasSubstr("3 of 3 scenario files run, 1 passed"));
  EXPECT_THAT(html, HasSubstr("<td class=\"fail\">FAIL</td><td class=\"num\">2 / 3</td>"));
  // Without a run folder the name is not a link, and the reason takes the row's other columns.
  EXPECT_THAT(html, HasSubstr("<tr><td>broken &lt;spec&gt;</td><td class=\"fail\">INVALID</td>"
                              "<td colspan=\"3\">did not run: broken.textproto:2:1: "
                              "simulation.duration_s: must be positive</td></tr>"));
}

TEST(SuitePageTest, FewerRowsThanFilesIsIncompleteWhateverTheRowsSay) {
  const std::string html = SuitePageHtml("s", {Ran("a", SuiteVerdict::kPass)}, 4);
  EXPECT_THAT(html, HasSubstr("<span class=\"badge neutral\">INCOMPLETE</span>"));
  EXPECT_THAT(html, HasSubstr("1 of 4 scenario files run, 1 passed; the rest did not run"));
  EXPECT_THAT(SuitePageHtml("s", {}, 2), HasSubstr("0 of 2 scenario files run"));
  EXPECT_STREQ(SuiteVerdictWord(SuiteVerdict::kInvalid), "INVALID");
}

}  // namespace
}  // namespace hilrig::host
