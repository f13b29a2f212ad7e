#include "host/report/histogram_plot.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

HistogramPlot MetAndNotMet(std::vector<double> met, std::vector<double> not_met) {
  HistogramPlot plot;
  plot.title = "grasp_force";
  plot.x_label = "worst value (N)";
  plot.groups = {{"met", "#1A7F37", std::move(met)}, {"not met", "#CF222E", std::move(not_met)}};
  return plot;
}

TEST(HistogramPlotTest, ValuesFallInEqualBinsOverRoundEndsAndTheTopEdgeInTheLast) {
  HistogramPlot plot = MetAndNotMet({0, 0.05, 0.1, 0.95}, {1.0});
  plot.bins = 10;
  const HistogramBins bins = BinHistogram(plot);
  ASSERT_TRUE(bins.any);
  EXPECT_DOUBLE_EQ(bins.lo, 0);
  EXPECT_DOUBLE_EQ(bins.hi, 1);
  ASSERT_EQ(bins.counts.size(), 2u);
  ASSERT_EQ(bins.counts[0].size(), 10u);
  EXPECT_EQ(bins.counts[0][0], 2u);  // 0 and 0.05
  EXPECT_EQ(bins.counts[0][1], 1u);  // 0.1
  EXPECT_EQ(bins.counts[0][9], 1u);  // 0.95
  EXPECT_EQ(bins.counts[1][9], 1u);  // 1.0, the top edge
  EXPECT_EQ(bins.not_finite, 0u);
}

TEST(HistogramPlotTest, TheAxisReachesTheLinesAndLeavesNonFiniteValuesOut) {
  HistogramPlot plot = MetAndNotMet({0.3, kNaN, 0.6}, {kInf, -kInf});
  plot.lines = {{"lower 0.25 N", 0.25}, {"upper 0.65 N", 0.65}, {"not drawn", kNaN}};
  const HistogramBins bins = BinHistogram(plot);
  EXPECT_LE(bins.lo, 0.25);
  EXPECT_GE(bins.hi, 0.65);
  EXPECT_EQ(bins.not_finite, 3u);
  std::uint64_t counted = 0;
  for (const auto& group : bins.counts) {
    for (const std::uint64_t count : group) counted += count;
  }
  EXPECT_EQ(counted, 2u);
  const std::string svg = RenderHistogramSvg(plot);
  EXPECT_THAT(svg, HasSubstr(">3 not finite, not drawn</text>"));
  EXPECT_THAT(svg, HasSubstr(">met (2)</text>"));
  EXPECT_THAT(svg, HasSubstr(">not met (0)</text>"));
  EXPECT_THAT(svg, HasSubstr(">upper 0.65 N</text>"));
  // Two limit lines across the plot; the NaN one is neither drawn nor in the legend.
  const std::size_t limits = svg.find("<g class=\"limits\"");
  ASSERT_NE(limits, std::string::npos);
  const std::string group = svg.substr(limits, svg.find("</g>", limits) - limits);
  EXPECT_EQ(std::count(group.begin(), group.end(), '\n'), 3) << group;  // the <g> and two lines
  EXPECT_THAT(svg, Not(HasSubstr(">not drawn</text>")));
  EXPECT_THAT(svg, Not(HasSubstr("nan")));
  EXPECT_THAT(svg, Not(HasSubstr("inf")));
}

TEST(HistogramPlotTest, OneRepeatedValueGetsAnAxisAroundIt) {
  const HistogramBins bins = BinHistogram(MetAndNotMet({0, 0, 0}, {}));
  EXPECT_LT(bins.lo, 0);
  EXPECT_GT(bins.hi, 0);
  EXPECT_GT(bins.hi - bins.lo, 0.5);  // not a span lost in rounding
}

TEST(HistogramPlotTest, WithoutAFiniteValueItDrawsTheFrameAndSaysSo) {
  const HistogramPlot plot = MetAndNotMet({kNaN}, {});
  const HistogramBins bins = BinHistogram(plot);
  EXPECT_FALSE(bins.any);
  const std::string svg = RenderHistogramSvg(plot);
  EXPECT_THAT(svg, HasSubstr(">no finite value to draw</text>"));
  EXPECT_THAT(svg, HasSubstr("<g class=\"bars\">\n</g>"));  // no bar
  EXPECT_THAT(svg, HasSubstr("<rect class=\"frame\""));
}

TEST(HistogramPlotTest, BarsStackTheGroupsInTheirColoursAndTextIsEscaped) {
  HistogramPlot plot = MetAndNotMet({0.5, 0.5}, {0.5});
  plot.title = "a <b> & c";
  plot.bins = 1;
  const std::string svg = RenderHistogramSvg(plot);
  EXPECT_THAT(svg, HasSubstr("a &lt;b&gt; &amp; c"));
  const std::size_t met = svg.find("fill=\"#1A7F37\"/>");
  const std::size_t not_met = svg.find("fill=\"#CF222E\"/>");
  ASSERT_NE(met, std::string::npos);
  ASSERT_NE(not_met, std::string::npos);
  EXPECT_LT(met, not_met);                   // the first group at the bottom, drawn first
  EXPECT_EQ(svg, RenderHistogramSvg(plot));  // deterministic
}

}  // namespace
}  // namespace hilrig::host
