#include "host/report/html_page.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(HtmlPageTest, TextIsEscapedForElementsAndAttributes) {
  EXPECT_EQ(HtmlText("a<b>&\"c'\x01"), "a&lt;b&gt;&amp;&quot;c&apos;?");
  EXPECT_EQ(TextCell("<x>").html, "&lt;x&gt;");
}

TEST(HtmlPageTest, NumbersShowFourSignificantDigitsAndWholeNumbersWhole) {
  EXPECT_EQ(PageNumber(0.60152230835650489), "0.6015");
  EXPECT_EQ(PageNumber(28.73), "28.73");
  EXPECT_EQ(PageNumber(1e-9), "1e-09");
  EXPECT_EQ(PageNumber(34000), "34000");
  EXPECT_EQ(PageNumber(-0.0), "0");
  EXPECT_EQ(PageNumber(123456.7), "1.235e+05");
  EXPECT_EQ(PageNumber(1e300), "1e+300");
}

TEST(HtmlPageTest, NumbersAreLocaleFreeAndNonFiniteOnesAreWords) {
  EXPECT_EQ(NumberCell(0.0123, "m").html, "0.0123 m");
  EXPECT_TRUE(NumberCell(1).numeric);
  EXPECT_EQ(NumberCell(std::numeric_limits<double>::quiet_NaN(), "N").html, "nan N");
  EXPECT_EQ(NumberCell(-std::numeric_limits<double>::infinity()).html, "-inf");
}

TEST(HtmlPageTest, ATableHasItsHeaderItsTonesAndPadsShortRows) {
  const std::string table =
      HtmlTable({"verdict", "name & unit", "value"},
                {{TextCell("PASS", Tone::kPass), TextCell("a"), NumberCell(2)},
                 {TextCell("FAIL", Tone::kFail)}});
  EXPECT_THAT(table, HasSubstr("<div class=\"wide\"><table>"));
  EXPECT_THAT(table, HasSubstr("<th>verdict</th><th>name &amp; unit</th><th>value</th>"));
  EXPECT_THAT(table,
              HasSubstr("<tr><td class=\"pass\">PASS</td><td>a</td><td class=\"num\">2</td></tr>"));
  EXPECT_THAT(table, HasSubstr("<tr><td class=\"fail\">FAIL</td><td></td><td></td></tr>"));
}

TEST(HtmlPageTest, ACellCanSpanColumnsAndTheRowIsPaddedAfterIt) {
  const std::string table =
      HtmlTable({"a", "b", "c"}, {{{"<code>x</code>", Tone::kPlain, false, 2}}});
  EXPECT_THAT(table, HasSubstr("<tr><td colspan=\"2\"><code>x</code></td><td></td></tr>"));
}

TEST(HtmlPageTest, FileLinksAreRelativeAndEscaped) {
  EXPECT_EQ(HtmlFileLinks({"report.json", "a&b.csv"}),
            "<h2>Files</h2>\n<p><a href=\"report.json\">report.json</a> "
            "<a href=\"a%26b.csv\">a&amp;b.csv</a> </p>\n");
}

// A space, '#' or '?' in a file name would cut the link short or make it a query: every byte
// outside the unreserved set and '/' is percent-encoded, the shown text only escaped.
TEST(HtmlPageTest, ALinkPercentEncodesItsPath) {
  EXPECT_EQ(HtmlLink("grasp #2/index.html", "grasp #2"),
            "<a href=\"grasp%20%232/index.html\">grasp #2</a>");
  EXPECT_EQ(HtmlLink("a?b<c>/x_y-z~1.html", "<a>"),
            "<a href=\"a%3Fb%3Cc%3E/x_y-z~1.html\">&lt;a&gt;</a>");
  EXPECT_EQ(HtmlLink("caf\xC3\xA9.html", "caf\xC3\xA9"),
            "<a href=\"caf%C3%A9.html\">caf\xC3\xA9</a>");
}

TEST(HtmlPageTest, ABadgeCarriesItsToneAndEscapedText) {
  EXPECT_EQ(HtmlBadge("PASS", Tone::kPass), "<span class=\"badge pass\">PASS</span>");
  EXPECT_EQ(HtmlBadge("<?>", Tone::kNeutral), "<span class=\"badge neutral\">&lt;?&gt;</span>");
}

TEST(HtmlPageTest, AnInlinedSvgLosesItsDeclarationAndPrefixesItsIds) {
  const std::string svg =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg><defs><clipPath id=\"area\"><rect/>"
      "</clipPath></defs><g clip-path=\"url(#area)\"/><text>grid=\"x\"</text></svg>\n";
  EXPECT_EQ(InlineSvg(svg, "p1-"),
            "<svg><defs><clipPath id=\"p1-area\"><rect/></clipPath></defs>"
            "<g clip-path=\"url(#p1-area)\"/><text>grid=\"x\"</text></svg>\n");
  EXPECT_EQ(InlineSvg("<svg/>", "p-"), "<svg/>");
}

TEST(HtmlPageTest, TheDocumentIsSelfContainedAndEscapesItsTitle) {
  const std::string page = HtmlDocument("a <b>", "<p>body</p>\n");
  EXPECT_EQ(page.rfind("<!DOCTYPE html>\n", 0), 0u);
  EXPECT_THAT(page, HasSubstr("<meta charset=\"utf-8\">"));
  EXPECT_THAT(page, HasSubstr("content=\"default-src 'none'; style-src 'unsafe-inline'\""));
  EXPECT_THAT(page, HasSubstr("<title>a &lt;b&gt;</title>"));
  EXPECT_THAT(page, HasSubstr("<body>\n<p>body</p>\n</body>\n</html>\n"));
  EXPECT_THAT(page, Not(HasSubstr("<script")));
  EXPECT_THAT(page, Not(HasSubstr("http://")));
  EXPECT_THAT(page, Not(HasSubstr("https://")));
}

}  // namespace
}  // namespace hilrig::host
