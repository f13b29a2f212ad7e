#include "host/report/svg_plot.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPxTolerance = 0.006;  // coordinates are written with 2 decimals

// ------------------------------------------------------------------------------------------------
// A small XML reader: enough to check well-formedness and pull elements and attributes out.

bool ValidEntityAt(const std::string& text, std::size_t amp) {
  for (const char* entity : {"&amp;", "&lt;", "&gt;", "&quot;", "&apos;"}) {
    if (text.compare(amp, std::string(entity).size(), entity) == 0) return true;
  }
  return false;
}

bool CharDataOk(const std::string& text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '<') return false;
    if (text[i] == '&' && !ValidEntityAt(text, i)) return false;
  }
  return true;
}

bool IsNameChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == ':' ||
         c == '.';
}

// "" when xml is one well-formed element (after an optional declaration), else what is wrong.
std::string WellFormedError(const std::string& xml) {
  std::vector<std::string> open;
  bool root_done = false, root_seen = false;
  std::size_t i = 0;
  while (i < xml.size()) {
    if (xml[i] != '<') {
      const std::size_t end = std::min(xml.find('<', i), xml.size());
      const std::string text = xml.substr(i, end - i);
      if (!CharDataOk(text)) return "bad character data near offset " + std::to_string(i);
      if (open.empty() && text.find_first_not_of(" \n\r\t") != std::string::npos) {
        return "text outside the root element";
      }
      i = end;
      continue;
    }
    if (xml.compare(i, 2, "<?") == 0) {
      if (root_seen) return "declaration after the root";
      const std::size_t end = xml.find("?>", i);
      if (end == std::string::npos) return "unterminated declaration";
      i = end + 2;
      continue;
    }
    if (xml.compare(i, 2, "</") == 0) {
      const std::size_t end = xml.find('>', i);
      if (end == std::string::npos) return "unterminated end tag";
      const std::string name = xml.substr(i + 2, end - i - 2);
      if (open.empty() || open.back() != name) return "mismatched </" + name + ">";
      open.pop_back();
      root_done = open.empty();
      i = end + 1;
      continue;
    }
    if (root_done) return "second root element";
    root_seen = true;
    std::size_t j = i + 1;
    while (j < xml.size() && IsNameChar(xml[j])) ++j;
    const std::string name = xml.substr(i + 1, j - i - 1);
    if (name.empty()) return "empty tag name at offset " + std::to_string(i);
    while (true) {
      while (j < xml.size() && std::isspace(static_cast<unsigned char>(xml[j]))) ++j;
      if (j >= xml.size()) return "unterminated tag <" + name;
      if (xml.compare(j, 2, "/>") == 0) {
        j += 2;
        root_done = open.empty();
        break;
      }
      if (xml[j] == '>') {
        open.push_back(name);
        ++j;
        break;
      }
      const std::size_t attr_start = j;
      while (j < xml.size() && IsNameChar(xml[j])) ++j;
      if (j == attr_start || j + 1 >= xml.size() || xml[j] != '=')
        return "bad attribute in " + name;
      const char quote = xml[j + 1];
      if (quote != '"' && quote != '\'') return "unquoted attribute in " + name;
      const std::size_t value_end = xml.find(quote, j + 2);
      if (value_end == std::string::npos) return "unterminated attribute in " + name;
      if (!CharDataOk(xml.substr(j + 2, value_end - j - 2))) return "bad attribute value";
      j = value_end + 1;
    }
    i = j;
  }
  if (!open.empty()) return "unclosed <" + open.back() + ">";
  if (!root_seen) return "no root element";
  return "";
}

using Attributes = std::map<std::string, std::string>;

// Attributes of every <tag ...> in xml, in document order.
std::vector<Attributes> Elements(const std::string& xml, const std::string& tag) {
  std::vector<Attributes> found;
  const std::string opening = "<" + tag;
  for (std::size_t at = xml.find(opening); at != std::string::npos;
       at = xml.find(opening, at + 1)) {
    std::size_t j = at + opening.size();
    if (j >= xml.size() || IsNameChar(xml[j])) continue;
    const std::size_t end = xml.find('>', j);
    Attributes attributes;
    while (j < end) {
      while (j < end && !IsNameChar(xml[j])) ++j;
      const std::size_t name_start = j;
      while (j < end && IsNameChar(xml[j])) ++j;
      if (j >= end || xml[j] != '=') break;
      const char quote = xml[j + 1];
      const std::size_t value_end = xml.find(quote, j + 2);
      attributes[xml.substr(name_start, j - name_start)] = xml.substr(j + 2, value_end - j - 2);
      j = value_end + 1;
    }
    found.push_back(attributes);
  }
  return found;
}

// The text between <g class="NAME"...> and its </g> (groups here are not nested).
std::string Group(const std::string& xml, const std::string& name) {
  const std::size_t start = xml.find("<g class=\"" + name + "\"");
  if (start == std::string::npos) return "";
  const std::size_t end = xml.find("</g>", start);
  return xml.substr(start, end - start);
}

std::vector<std::string> AllGroups(const std::string& xml, const std::string& name) {
  std::vector<std::string> groups;
  const std::string opening = "<g class=\"" + name + "\"";
  for (std::size_t at = xml.find(opening); at != std::string::npos;
       at = xml.find(opening, at + 1)) {
    groups.push_back(xml.substr(at, xml.find("</g>", at) - at));
  }
  return groups;
}

struct Xy {
  double x = 0, y = 0;
};

std::vector<std::vector<Xy>> Polylines(const std::string& xml) {
  std::vector<std::vector<Xy>> lines;
  for (const Attributes& polyline : Elements(xml, "polyline")) {
    std::vector<Xy> points;
    std::istringstream in(polyline.at("points"));
    std::string pair;
    while (in >> pair) {
      const std::size_t comma = pair.find(',');
      points.push_back({std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1))});
    }
    lines.push_back(points);
  }
  return lines;
}

double Num(const Attributes& attributes, const std::string& name) {
  return std::stod(attributes.at(name));
}

// The plot area of a 900 x 360 document with one legend row, from the documented margins.
PlotRect ExpectedAreaOneLegendRow() {
  const double height = 360 - kPlotMarginTopPx - kAxisBelowPx - (kLegendGapPx + kLegendRowPx);
  return {kPlotMarginLeftPx, kPlotMarginTopPx, 900 - kPlotMarginLeftPx - kPlotMarginRightPx,
          height};
}

double ExpectedX(const PlotRect& area, double t, double lo, double hi) {
  return area.left_px + (t - lo) / (hi - lo) * area.width_px;
}
double ExpectedY(const PlotRect& area, double v, double lo, double hi) {
  return area.top_px + area.height_px - (v - lo) / (hi - lo) * area.height_px;
}

PlotSeries Series(std::string name, std::vector<double> time_s, std::vector<double> value) {
  PlotSeries series;
  series.name = std::move(name);
  series.time_s = std::move(time_s);
  series.value = std::move(value);
  return series;
}

// A series over 0..30 s whose values span 0..1, so the axes are x 0..30 and y -0.05..1.05.
PlotSeries UnitSeries() { return Series("unit", {0, 10, 20, 30}, {0, 1, 0.5, 0.25}); }

// ------------------------------------------------------------------------------------------------
// The checker itself must be able to say no.

TEST(WellFormedCheckerTest, RejectsBrokenDocuments) {
  EXPECT_EQ(WellFormedError("<svg><g></g></svg>"), "");
  EXPECT_NE(WellFormedError("<svg><g></svg>"), "");
  EXPECT_NE(WellFormedError("<svg><text>a < b</text></svg>"), "");
  EXPECT_NE(WellFormedError("<svg><text>a & b</text></svg>"), "");
  EXPECT_NE(WellFormedError("<svg a=\"x\"/><svg/>"), "");
}

// ------------------------------------------------------------------------------------------------
// Ticks.

TEST(NiceTicksTest, ForceRangeGetsTenthSteps) {
  const AxisTicks ticks = NiceTicks(0, 0.65, TickFit::kExtendToTicks);

  EXPECT_DOUBLE_EQ(ticks.step, 0.1);
  EXPECT_DOUBLE_EQ(ticks.lo, 0);
  EXPECT_DOUBLE_EQ(ticks.hi, 0.7);
  EXPECT_THAT(ticks.labels, ElementsAre("0.0", "0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7"));
}

TEST(NiceTicksTest, ThirtySecondsGetsFiveSecondSteps) {
  const AxisTicks ticks = NiceTicks(0, 30, TickFit::kExtendToTicks);

  EXPECT_DOUBLE_EQ(ticks.step, 5);
  EXPECT_THAT(ticks.values, ElementsAre(0, 5, 10, 15, 20, 25, 30));
  EXPECT_THAT(ticks.labels, ElementsAre("0", "5", "10", "15", "20", "25", "30"));
}

TEST(NiceTicksTest, ExtendWidensToEnclosingSteps) {
  const AxisTicks ticks = NiceTicks(3, 97, TickFit::kExtendToTicks);

  EXPECT_DOUBLE_EQ(ticks.step, 20);
  EXPECT_THAT(ticks.values, ElementsAre(0, 20, 40, 60, 80, 100));
  EXPECT_DOUBLE_EQ(ticks.lo, 0);
  EXPECT_DOUBLE_EQ(ticks.hi, 100);
}

TEST(NiceTicksTest, WithinKeepsTheRangeAndLabelsInsideIt) {
  const AxisTicks ticks = NiceTicks(-0.05, 1.05, TickFit::kTicksWithin);

  EXPECT_DOUBLE_EQ(ticks.lo, -0.05);
  EXPECT_DOUBLE_EQ(ticks.hi, 1.05);
  EXPECT_DOUBLE_EQ(ticks.step, 0.2);
  EXPECT_THAT(ticks.labels, ElementsAre("0.0", "0.2", "0.4", "0.6", "0.8", "1.0"));
}

TEST(NiceTicksTest, SmallNegativeRangeUsesTwoDecimals) {
  const AxisTicks ticks = NiceTicks(-0.0123, 0.0456, TickFit::kExtendToTicks);

  EXPECT_DOUBLE_EQ(ticks.step, 0.01);
  EXPECT_THAT(ticks.labels,
              ElementsAre("-0.02", "-0.01", "0.00", "0.01", "0.02", "0.03", "0.04", "0.05"));
}

TEST(NiceTicksTest, FourToEightTicksAcrossScales) {
  const std::vector<std::pair<double, double>> ranges = {
      {0, 1}, {0, 0.65}, {-3, 7}, {12.5, 13.1}, {0, 30}, {0, 123456}, {-1e-4, 3e-4}, {1, 1.0001}};
  for (const auto& [lo, hi] : ranges) {
    for (TickFit fit : {TickFit::kExtendToTicks, TickFit::kTicksWithin}) {
      const AxisTicks ticks = NiceTicks(lo, hi, fit);
      EXPECT_GE(ticks.values.size(), 4u) << lo << ".." << hi;
      EXPECT_LE(ticks.values.size(), 8u) << lo << ".." << hi;
      const double mantissa = ticks.step / std::pow(10.0, std::floor(std::log10(ticks.step)));
      EXPECT_TRUE(std::abs(mantissa - 1) < 1e-9 || std::abs(mantissa - 2) < 1e-9 ||
                  std::abs(mantissa - 5) < 1e-9)
          << ticks.step;
    }
  }
}

TEST(NiceTicksTest, DegenerateAndNonFiniteRangesStillGiveAnAxis) {
  for (const auto& [lo, hi] :
       std::vector<std::pair<double, double>>{{2, 2}, {kNaN, 1}, {0, kInf}, {5, -5}}) {
    const AxisTicks ticks = NiceTicks(lo, hi, TickFit::kTicksWithin);
    EXPECT_TRUE(std::isfinite(ticks.lo) && std::isfinite(ticks.hi)) << lo << ".." << hi;
    EXPECT_LT(ticks.lo, ticks.hi) << lo << ".." << hi;
    EXPECT_FALSE(ticks.values.empty()) << lo << ".." << hi;
  }
}

// ------------------------------------------------------------------------------------------------
// Layout and coordinates.

TEST(LayoutTest, PlotAreaFollowsTheDocumentedMargins) {
  TimePlot plot;
  plot.series = {UnitSeries()};

  const PlotLayout layout = LayoutOf(plot);

  const PlotRect expected = ExpectedAreaOneLegendRow();
  EXPECT_EQ(layout.doc_width_px, 900);
  EXPECT_EQ(layout.doc_height_px, 360);
  EXPECT_DOUBLE_EQ(layout.area.left_px, expected.left_px);
  EXPECT_DOUBLE_EQ(layout.area.top_px, expected.top_px);
  EXPECT_DOUBLE_EQ(layout.area.width_px, expected.width_px);
  EXPECT_DOUBLE_EQ(layout.area.height_px, expected.height_px);
}

TEST(RenderSvgTest, SeriesMapsToExpectedPixels) {
  TimePlot plot;
  plot.series = {UnitSeries()};

  const std::string svg = RenderSvg(plot);

  // x: 0..30 s exactly (already on 5 s ticks); y: 0..1 padded by 5 % each side.
  const PlotRect area = ExpectedAreaOneLegendRow();
  const auto lines = Polylines(svg);
  ASSERT_EQ(lines.size(), 1u);
  ASSERT_EQ(lines[0].size(), 4u);
  const std::vector<double> t = {0, 10, 20, 30}, v = {0, 1, 0.5, 0.25};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(lines[0][i].x, ExpectedX(area, t[i], 0, 30), kPxTolerance) << i;
    EXPECT_NEAR(lines[0][i].y, ExpectedY(area, v[i], -0.05, 1.05), kPxTolerance) << i;
  }
}

TEST(RenderSvgTest, DocumentIsStandaloneSvg) {
  TimePlot plot;
  plot.series = {UnitSeries()};

  const std::string svg = RenderSvg(plot);

  EXPECT_EQ(svg.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"", 0), 0u);
  const auto roots = Elements(svg, "svg");
  ASSERT_EQ(roots.size(), 1u);
  EXPECT_EQ(roots[0].at("xmlns"), "http://www.w3.org/2000/svg");
  EXPECT_EQ(roots[0].at("version"), "1.1");
  EXPECT_EQ(roots[0].at("width"), "900");
  EXPECT_EQ(roots[0].at("height"), "360");
  EXPECT_EQ(roots[0].at("viewBox"), "0 0 900 360");
  EXPECT_EQ(WellFormedError(svg), "");
}

TEST(RenderSvgTest, AxesCarryTitleLabelsAndTickLabels) {
  TimePlot plot;
  plot.title = "grasp force";
  plot.y_label = "force (N)";
  plot.series = {UnitSeries()};

  const std::string svg = RenderSvg(plot);

  EXPECT_THAT(svg, HasSubstr(">grasp force</text>"));
  EXPECT_THAT(svg, HasSubstr(">time (s)</text>"));
  EXPECT_THAT(svg, HasSubstr("class=\"y-label\" transform=\"rotate(-90"));
  const std::string ticks = Group(svg, "tick-labels");
  for (const char* label : {">0<", ">15<", ">30<", ">0.0<", ">0.4<", ">1.0<"}) {
    EXPECT_THAT(ticks, HasSubstr(label));
  }
  EXPECT_THAT(svg, Not(HasSubstr("0000000")));
}

TEST(RenderSvgTest, NanSplitsTheLineInTwo) {
  TimePlot plot;
  plot.series = {Series("gap", {0, 1, 2, 3, 4, 5}, {1, 2, kNaN, 3, 4, 5})};

  const auto lines = Polylines(RenderSvg(plot));

  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].size(), 2u);
  EXPECT_EQ(lines[1].size(), 3u);
}

TEST(RenderSvgTest, PointsStayInsideThePlotArea) {
  TimePlot plot;
  plot.series = {Series("wide", {-1e308, 0, 1e308}, {1e308, -1e308, 3}), UnitSeries()};

  const std::string svg = RenderSvg(plot);

  const PlotRect area = LayoutOf(plot).area;
  for (const auto& line : Polylines(svg)) {
    for (const Xy& p : line) {
      EXPECT_GE(p.x, area.left_px - kPxTolerance);
      EXPECT_LE(p.x, area.left_px + area.width_px + kPxTolerance);
      EXPECT_GE(p.y, area.top_px - kPxTolerance);
      EXPECT_LE(p.y, area.top_px + area.height_px + kPxTolerance);
    }
  }
  EXPECT_EQ(WellFormedError(svg), "");
}

TEST(RenderSvgTest, SinglePointGetsANonDegenerateRangeAndIsCentred) {
  TimePlot plot;
  plot.series = {Series("one", {5}, {0.3})};

  const std::string svg = RenderSvg(plot);

  const auto circles = Elements(svg, "circle");
  ASSERT_EQ(circles.size(), 1u);
  const PlotRect area = LayoutOf(plot).area;
  EXPECT_NEAR(Num(circles[0], "cx"), area.left_px + area.width_px / 2, kPxTolerance);
  EXPECT_NEAR(Num(circles[0], "cy"), area.top_px + area.height_px / 2, kPxTolerance);
  EXPECT_GE(Elements(Group(svg, "tick-labels"), "text").size(), 8u);  // both axes labelled
}

TEST(RenderSvgTest, PaletteIsUsedInOrderForSeriesWithoutColour) {
  TimePlot plot;
  plot.series = {UnitSeries(), UnitSeries(), UnitSeries()};
  plot.series[1].color = "purple";

  const std::string svg = RenderSvg(plot);

  const auto groups = AllGroups(svg, "series");
  ASSERT_EQ(groups.size(), 3u);
  EXPECT_THAT(groups[0], HasSubstr(std::string("stroke=\"") + kSeriesPalette[0] + "\""));
  EXPECT_THAT(groups[1], HasSubstr("stroke=\"purple\""));
  EXPECT_THAT(groups[2], HasSubstr(std::string("stroke=\"") + kSeriesPalette[1] + "\""));
}

// ------------------------------------------------------------------------------------------------
// Decimation.

TEST(DecimateTest, BucketKeepsMinAndMaxInSampleOrder) {
  const std::vector<double> t = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const std::vector<double> v = {0, 5, 1, -3, 2, 7, 1, -1, 4, 0};

  const auto points = DecimateMinMax(t, v, 4);  // 2 buckets of 5

  ASSERT_EQ(points.size(), 4u);
  const std::vector<std::pair<double, double>> expected = {{1, 5}, {3, -3}, {5, 7}, {7, -1}};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(points[i].time_s, expected[i].first) << i;
    EXPECT_EQ(points[i].value, expected[i].second) << i;
  }
}

TEST(DecimateTest, GapInsideABucketSurvives) {
  const std::vector<double> t = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const std::vector<double> v = {0, 5, kNaN, -3, 2, 7, 1, -1, 4, 0};

  const auto points = DecimateMinMax(t, v, 4);

  ASSERT_EQ(points.size(), 5u);
  EXPECT_EQ(points[0].value, 5);
  EXPECT_TRUE(std::isnan(points[1].value));
  EXPECT_EQ(points[2].value, -3);
}

TEST(DecimateTest, SingleSampleSpikeSurvivesAndCountIsBounded) {
  std::vector<double> t(100000), v(100000, 0.0);
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = i * 0.001;
  v[54321] = 10;

  const auto points = DecimateMinMax(t, v, 2000);

  EXPECT_LE(points.size(), 2000u);
  const auto spike =
      std::find_if(points.begin(), points.end(), [](const PlotPoint& p) { return p.value == 10; });
  ASSERT_NE(spike, points.end());
  EXPECT_DOUBLE_EQ(spike->time_s, 54.321);
}

TEST(DecimateTest, ShortSeriesIsUnchanged) {
  const auto points = DecimateMinMax({0, 1, 2}, {3, 4, 5}, 2000);

  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[2].time_s, 2);
  EXPECT_EQ(points[2].value, 5);
}

TEST(RenderSvgTest, LongSeriesIsDecimatedButKeepsItsSpike) {
  TimePlot plot;
  PlotSeries series;
  for (int i = 0; i < 50000; ++i) {
    series.time_s.push_back(i * 0.001);
    series.value.push_back(i == 31415 ? 1.0 : 0.01 * std::sin(i * 0.37));
  }
  plot.series = {series};
  plot.max_points_per_series = 100;

  const std::string svg = RenderSvg(plot);

  const auto lines = Polylines(svg);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_LE(lines[0].size(), 100u);
  const double top_y =
      std::min_element(lines[0].begin(), lines[0].end(), [](Xy a, Xy b) { return a.y < b.y; })->y;
  const PlotRect area = LayoutOf(plot).area;
  // The spike is the data maximum: 5 % of the span below the top of the frame.
  const double span = 1.0 - (-0.01);
  EXPECT_NEAR(top_y, ExpectedY(area, 1.0, -0.01 - 0.05 * span, 1.0 + 0.05 * span), 0.05);
}

// ------------------------------------------------------------------------------------------------
// Bands.

// The fill is the allowed region: below an upper limit, so down to the bottom edge of the frame.
TEST(RenderSvgTest, UpperOnlyBandFillsDownToTheBottomEdge) {
  TimePlot plot;
  plot.series = {UnitSeries()};
  PlotBand band;
  band.name = "ceiling";
  band.upper = 0.8;
  band.from_s = 5;
  plot.bands = {band};
  plot.width_px = 500;  // one legend column: two rows, so the area differs from one row

  const std::string svg = RenderSvg(plot);

  const double height = 360 - kPlotMarginTopPx - kAxisBelowPx - (kLegendGapPx + 2 * kLegendRowPx);
  const PlotRect area = {kPlotMarginLeftPx, kPlotMarginTopPx,
                         500 - kPlotMarginLeftPx - kPlotMarginRightPx, height};
  const auto rects = Elements(Group(svg, "band"), "rect");
  ASSERT_EQ(rects.size(), 1u);
  const double limit_y = ExpectedY(area, 0.8, -0.05, 1.05);
  EXPECT_NEAR(Num(rects[0], "y"), limit_y, kPxTolerance);
  EXPECT_NEAR(Num(rects[0], "height"), area.top_px + area.height_px - limit_y, 2 * kPxTolerance);
  EXPECT_NEAR(Num(rects[0], "x"), ExpectedX(area, 5, 0, 30), kPxTolerance);
  EXPECT_NEAR(Num(rects[0], "width"), ExpectedX(area, 30, 0, 30) - ExpectedX(area, 5, 0, 30),
              2 * kPxTolerance);
  const auto limits = Elements(Group(svg, "band"), "line");
  ASSERT_EQ(limits.size(), 1u);
  EXPECT_NEAR(Num(limits[0], "y1"), limit_y, kPxTolerance);
}

// Above a lower limit the allowed region reaches the top edge.
TEST(RenderSvgTest, LowerOnlyBandFillsUpToTheTopEdge) {
  TimePlot plot;
  plot.series = {UnitSeries()};
  PlotBand band;
  band.name = "floor";
  band.lower = 0.2;
  plot.bands = {band};

  const std::string svg = RenderSvg(plot);

  const PlotRect area = ExpectedAreaOneLegendRow();
  const auto rects = Elements(Group(svg, "band"), "rect");
  ASSERT_EQ(rects.size(), 1u);
  EXPECT_NEAR(Num(rects[0], "y"), area.top_px, kPxTolerance);
  EXPECT_NEAR(Num(rects[0], "height"), ExpectedY(area, 0.2, -0.05, 1.05) - area.top_px,
              2 * kPxTolerance);
  EXPECT_NEAR(Num(rects[0], "x"), area.left_px, kPxTolerance);
  EXPECT_NEAR(Num(rects[0], "width"), area.width_px, 2 * kPxTolerance);
}

TEST(RenderSvgTest, BandLimitsWidenTheValueRange) {
  TimePlot plot;
  plot.series = {UnitSeries()};
  PlotBand band;
  band.lower = -1;
  band.upper = 3;
  plot.bands = {band};

  const std::string svg = RenderSvg(plot);

  // y covers -1..3 padded by 0.2 each side; the band fills all but the padding.
  const PlotRect area = LayoutOf(plot).area;
  const auto rects = Elements(Group(svg, "band"), "rect");
  ASSERT_EQ(rects.size(), 1u);
  EXPECT_NEAR(Num(rects[0], "y"), ExpectedY(area, 3, -1.2, 3.2), kPxTolerance);
  EXPECT_NEAR(Num(rects[0], "height"),
              ExpectedY(area, -1, -1.2, 3.2) - ExpectedY(area, 3, -1.2, 3.2), 2 * kPxTolerance);
}

TEST(RenderSvgTest, LegendDescribesBandsWithTheUnitOfTheYLabel) {
  TimePlot plot;
  plot.y_label = "force (N)";
  plot.series = {UnitSeries()};
  PlotBand band;
  band.name = "envelope grasp_force";
  band.lower = 0.25;
  band.upper = 0.65;
  plot.bands = {band};

  const std::string svg = RenderSvg(plot);

  EXPECT_THAT(Group(svg, "legend"), HasSubstr(">envelope grasp_force: 0.25\xE2\x80\x93"
                                              "0.65 N</text>"));
  EXPECT_THAT(Group(svg, "legend"), HasSubstr(">unit</text>"));
}

TEST(RenderSvgTest, ExpectFailBandIsDashedRedAndSaysSo) {
  TimePlot plot;
  plot.y_label = "angle (rad)";
  plot.series = {UnitSeries()};
  PlotBand band;
  band.name = "ablation";
  band.upper = 0.5;
  band.expect_fail = true;
  plot.bands = {band};

  const std::string svg = RenderSvg(plot);

  EXPECT_EQ(Group(svg, "band"), "");
  const std::string group = Group(svg, "band-fail");
  ASSERT_NE(group, "");
  EXPECT_THAT(group, HasSubstr("stroke-dasharray"));
  EXPECT_THAT(group, HasSubstr("#C00000"));
  EXPECT_THAT(Group(svg, "legend"), HasSubstr("ablation: \xE2\x89\xA4 0.5 rad (expected to fail)"));
}

TEST(RenderSvgTest, BandOutsideThePlottedTimeIsNotDrawn) {
  TimePlot plot;
  plot.series = {UnitSeries()};
  PlotBand band;
  band.name = "late";
  band.lower = 0.1;
  band.from_s = 100;
  band.until_s = 200;
  plot.bands = {band};

  const std::string svg = RenderSvg(plot);

  EXPECT_EQ(Elements(Group(svg, "band"), "rect").size(), 0u);
  EXPECT_THAT(Group(svg, "legend"), HasSubstr("late: \xE2\x89\xA5 0.1 over 100\xE2\x80\x93"
                                              "200 s"));
}

// ------------------------------------------------------------------------------------------------
// Text, validity, determinism.

TEST(RenderSvgTest, EscapesEveryXmlSpecialCharacter) {
  TimePlot plot;
  plot.title = "a<b & \"c\" 'd'>";
  plot.y_label = "x <&> (N)";
  plot.series = {Series("s<1>&'\"", {0, 1}, {0, 1})};
  plot.series[0].color = "red\" onload=\"x";

  const std::string svg = RenderSvg(plot);

  EXPECT_THAT(svg, HasSubstr("a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;"));
  EXPECT_THAT(svg, HasSubstr("s&lt;1&gt;&amp;&apos;&quot;"));
  EXPECT_THAT(svg, Not(HasSubstr("a<b")));
  EXPECT_THAT(svg, Not(HasSubstr("onload=\"")));
  EXPECT_EQ(WellFormedError(svg), "");
}

TimePlot RichPlot() {
  TimePlot plot;
  plot.title = "position & force";
  plot.y_label = "error (m)";
  plot.series = {UnitSeries(), Series("noisy", {0, 1, 2, 3, 4}, {0.1, kNaN, -0.2, kInf, 0.4})};
  plot.series[1].dashed = true;
  PlotBand pass, fail;
  pass.name = "envelope z";
  pass.lower = -0.1;
  pass.upper = 0.9;
  fail.name = "ablation z";
  fail.upper = 0.2;
  fail.from_s = 2;
  fail.until_s = 25;
  fail.expect_fail = true;
  plot.bands = {pass, fail};
  return plot;
}

TEST(RenderSvgTest, SamePlotGivesIdenticalText) {
  TimePlot other;
  other.series = {Series("other", {0, 1}, {5, 6})};

  const std::string first = RenderSvg(RichPlot());
  const std::string in_between = RenderSvg(other);
  const std::string second = RenderSvg(RichPlot());

  EXPECT_EQ(first, second);
  EXPECT_NE(first, in_between);
}

TEST(RenderSvgTest, RichPlotIsWellFormed) { EXPECT_EQ(WellFormedError(RenderSvg(RichPlot())), ""); }

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

TEST(RenderSvgTest, NonFiniteInputNeverPrintsNanOrInf) {
  TimePlot plot;
  plot.series = {Series("bad", {0, kNaN, 2, kInf, 4}, {kNaN, 1, kInf, 2, -kInf}),
                 Series("huge", {0, 1}, {-1.7e308, 1.7e308})};
  PlotBand band;
  band.name = "broken";
  band.lower = kNaN;
  band.upper = kInf;
  band.from_s = kNaN;
  plot.bands = {band};
  plot.width_px = -3;
  plot.height_px = 0;

  const std::string svg = Lower(RenderSvg(plot));

  EXPECT_THAT(svg, Not(HasSubstr("nan")));
  EXPECT_THAT(svg, Not(HasSubstr("inf")));
  EXPECT_EQ(WellFormedError(svg), "");
  EXPECT_EQ(Elements(svg, "svg").at(0).at("width"), std::to_string(kMinWidthPx));
}

TEST(RenderSvgTest, NoFiniteDataDrawsAxesAndANote) {
  TimePlot plot;
  plot.series = {Series("all gaps", {0, 1, 2}, {kNaN, kInf, kNaN})};

  const std::string svg = RenderSvg(plot);

  EXPECT_THAT(svg, HasSubstr(">no data</text>"));
  EXPECT_EQ(Elements(svg, "rect class=\"frame\"").size(), 1u);
  EXPECT_EQ(Polylines(svg).size(), 0u);
  EXPECT_THAT(Lower(svg), Not(HasSubstr("nan")));
  EXPECT_EQ(WellFormedError(svg), "");
}

TEST(RenderSvgTest, EmptyPlotIsStillValid) {
  const std::string svg = RenderSvg(TimePlot{});

  EXPECT_THAT(svg, HasSubstr(">no data</text>"));
  EXPECT_EQ(WellFormedError(svg), "");
}

TEST(RenderSvgTest, LengthMismatchIsFlaggedInTheLegend) {
  TimePlot plot;
  plot.series = {Series("short", {0, 1, 2}, {1, 2})};

  const std::string svg = RenderSvg(plot);

  EXPECT_THAT(Group(svg, "legend"), HasSubstr("short (lengths differ: 3 times, 2 values)"));
  ASSERT_EQ(Polylines(svg).size(), 1u);
  EXPECT_EQ(Polylines(svg)[0].size(), 2u);
}

// A top view keeps shapes: a path from (0, 0) to (1, 1) in a wide plot is drawn at 45 degrees.
TEST(RenderSvgTest, EqualScaleGivesBothAxesTheSameUnitsPerPixel) {
  TimePlot plot;
  plot.x_label = "x (m)";
  plot.equal_scale = true;
  plot.series = {Series("path", {0, 1}, {0, 1})};
  const std::string svg = RenderSvg(plot);
  const auto lines = Polylines(svg);
  ASSERT_EQ(lines.size(), 1u);
  ASSERT_EQ(lines[0].size(), 2u);
  const double dx = lines[0][1].x - lines[0][0].x, dy = lines[0][0].y - lines[0][1].y;
  EXPECT_GT(dx, 50);
  EXPECT_NEAR(dx, dy, 0.02);
  EXPECT_NE(svg.find(">x (m)<"), std::string::npos);
  EXPECT_EQ(svg.find(">time (s)<"), std::string::npos);
  // Without it the same path in the same wide plot is far from 45 degrees.
  plot.equal_scale = false;
  const auto stretched = Polylines(RenderSvg(plot));
  EXPECT_GT(
      std::abs((stretched[0][1].x - stretched[0][0].x) / (stretched[0][0].y - stretched[0][1].y)),
      2.0);
}

TEST(RenderSvgTest, MarkersInTheTimeRangeAreDrawnWithTheirLabels) {
  TimePlot plot;
  plot.series = {Series("s", {0, 10}, {0, 1})};
  plot.markers = {{2, "grasp <0.6> N"}, {-5, "before"}, {std::nan(""), "nan"}, {8, "open"}};
  const std::string svg = RenderSvg(plot);
  EXPECT_EQ(WellFormedError(svg), "");
  EXPECT_NE(svg.find(">grasp &lt;0.6&gt; N<"), std::string::npos);
  EXPECT_NE(svg.find(">open<"), std::string::npos);
  EXPECT_EQ(svg.find("before"), std::string::npos);
  EXPECT_EQ(svg.find(">nan<"), std::string::npos);
  // Lines under the series, labels over them.
  EXPECT_LT(svg.find("class=\"markers\""), svg.find("class=\"series\""));
  EXPECT_GT(svg.find("class=\"marker-labels\""), svg.find("class=\"series\""));
}

TEST(RenderSvgGridTest, EachPanelIsANestedDocumentWithItsOwnClipPath) {
  TimePlot plot;
  plot.series = {Series("s", {0, 1}, {0, 1})};
  const std::string svg = RenderSvgGrid({plot, plot, plot}, 2);
  EXPECT_EQ(WellFormedError(svg), "");
  for (const char* id : {"plot-area-0", "plot-area-1", "plot-area-2"}) {
    EXPECT_NE(svg.find(std::string("id=\"") + id + "\""), std::string::npos) << id;
    EXPECT_NE(svg.find(std::string("url(#") + id + ")"), std::string::npos) << id;
  }
  EXPECT_EQ(Polylines(svg).size(), 3u);
  const PlotLayout layout = LayoutOf(plot);
  EXPECT_NE(svg.find("width=\"" + std::to_string(2 * layout.doc_width_px) + "\""),
            std::string::npos);
  EXPECT_NE(svg.find("height=\"" + std::to_string(2 * layout.doc_height_px) + "\""),
            std::string::npos);
}

// The pieces every plot kind draws the same way: the frame, the title, the turned y label and a
// legend swatch, each at the pixels it was given, its text escaped.
TEST(SvgBuildingBlocksTest, FrameTitleYLabelAndSwatchAreDrawnWhereTheyAreAsked) {
  EXPECT_EQ(SvgFrame({10, 20, 300.5, 40}),
            "<rect class=\"frame\" x=\"10.00\" y=\"20.00\" width=\"300.50\" height=\"40.00\" "
            "fill=\"none\" stroke=\"#333333\"/>\n");
  EXPECT_EQ(SvgTitle(400, "a < b"),
            "<text x=\"200.00\" y=\"22.00\" text-anchor=\"middle\" class=\"title\" "
            "font-size=\"14\" font-weight=\"bold\">a &lt; b</text>\n");
  EXPECT_EQ(SvgTitle(400, ""), "");
  EXPECT_EQ(SvgYLabel(16, 100, "force (N)"),
            "<text x=\"16.00\" y=\"100.00\" text-anchor=\"middle\" class=\"y-label\" "
            "transform=\"rotate(-90 16.00 100.00)\">force (N)</text>\n");
  EXPECT_EQ(SvgSwatch(5, 50, 24, "#0072B2", " stroke=\"#000000\""),
            "<rect x=\"5.00\" y=\"41.00\" width=\"24.00\" height=\"10\" fill=\"#0072B2\" "
            "stroke=\"#000000\"/>\n");
}

}  // namespace
}  // namespace hilrig::host
