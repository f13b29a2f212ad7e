#include "host/report/scatter_plot.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::Not;

TEST(LogTicksTest, SpansTheEnclosingDecades) {
  const LogAxis axis = LogTicks(0.003, 0.2);

  EXPECT_EQ(axis.lo_exponent, -3);
  EXPECT_EQ(axis.hi_exponent, 0);
  EXPECT_THAT(axis.tick_exponents, ElementsAre(-3, -2, -1, 0));
  EXPECT_THAT(axis.labels, ElementsAre("1e-3", "0.01", "0.1", "1"));
}

TEST(LogTicksTest, ASingleValueGetsOneDecade) {
  const LogAxis axis = LogTicks(100, 100);

  EXPECT_EQ(axis.lo_exponent, 2);
  EXPECT_EQ(axis.hi_exponent, 3);
}

TEST(LogTicksTest, ManyDecadesAreThinnedToEightTicksAtMost) {
  const LogAxis axis = LogTicks(1e-20, 1e5);  // 25 decades: every 4th

  EXPECT_EQ(axis.decade_step, 4);
  EXPECT_EQ(axis.tick_exponents.front(), -20);
  EXPECT_EQ(axis.tick_exponents[1], -16);
  EXPECT_LE(axis.tick_exponents.size(), 8u);
  EXPECT_EQ(axis.labels.back(), "1e+04");
}

TEST(LogTicksTest, UnusableRangesFallBackToOneToTen) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (auto [lo, hi] : {std::pair{0.0, 1.0}, {-1.0, 1.0}, {nan, 1.0}, {2.0, 1.0}}) {
    const LogAxis axis = LogTicks(lo, hi);
    EXPECT_EQ(axis.lo_exponent, 0);
    EXPECT_EQ(axis.hi_exponent, 1);
  }
}

TEST(LogAxisPxTest, MapsDecadesLinearlyAndClampsOutside) {
  const LogAxis axis = LogTicks(0.001, 1);  // 10^-3 .. 10^0 over 300 px from 100

  EXPECT_DOUBLE_EQ(LogAxisPx(axis, 0.01, 100, 300), 200);
  EXPECT_DOUBLE_EQ(LogAxisPx(axis, 1e-9, 100, 300), 100);
  EXPECT_DOUBLE_EQ(LogAxisPx(axis, 0.0, 100, 300), 100);
  EXPECT_DOUBLE_EQ(LogAxisPx(axis, 1e9, 100, 300), 400);
}

// Two points fix the axes at 10^-3..10^0 (x) and 10^-4..10^-1 (y); the default 640 x 440
// document with one legend entry has its plot area at x 72..616 (544 px) and y 36..374 (338 px:
// 440 - 36 top - 44 axis - 6 gap - 16 one legend row).
ScatterPlot TwoPointPlot() {
  ScatterPlot plot;
  plot.title = "work <precision>";
  plot.series.push_back({"RK4", "#123456", {{1e-3, 1e-4, "x1"}, {1, 0.1, "x8"}}});
  return plot;
}

TEST(RenderScatterSvgTest, PlacesAPointOnTheLogAxes) {
  ScatterPlot plot = TwoPointPlot();
  plot.series[0].points.push_back({0.1, 0.01, "mid"});

  const std::string svg = RenderScatterSvg(plot);

  // x: 72 + 2/3 x 544 = 434.67; y: 374 - 2/3 x 338 = 148.67
  EXPECT_THAT(svg, HasSubstr("cx=\"434.67\" cy=\"148.67\""));
  EXPECT_THAT(svg, HasSubstr(">mid</text>"));
  EXPECT_THAT(svg, HasSubstr("fill=\"#123456\""));
}

TEST(RenderScatterSvgTest, EscapesTheTitle) {
  const std::string svg = RenderScatterSvg(TwoPointPlot());

  EXPECT_THAT(svg, HasSubstr("work &lt;precision&gt;"));
  EXPECT_THAT(svg, Not(HasSubstr("<precision>")));
}

TEST(RenderScatterSvgTest, DrawsTheFrontThroughItsPoints) {
  ScatterPlot plot = TwoPointPlot();
  plot.front = {{1e-3, 0.1, ""}, {1, 1e-4, ""}};

  const std::string svg = RenderScatterSvg(plot);

  EXPECT_THAT(svg, HasSubstr("class=\"front\" points=\"72.00,36.00 616.00,374.00\""));
  EXPECT_THAT(svg, HasSubstr(">Pareto front</text>"));
}

TEST(RenderScatterSvgTest, ZeroAndNonFinitePointsAreLeftOutAndCounted) {
  ScatterPlot plot = TwoPointPlot();
  plot.series[0].points.push_back({0.1, 0.0, "zero"});
  plot.series[0].points.push_back({std::numeric_limits<double>::infinity(), 0.01, "inf"});

  const std::string svg = RenderScatterSvg(plot);

  EXPECT_THAT(svg, HasSubstr("2 points not drawn (zero or not finite)"));
  EXPECT_THAT(svg, Not(HasSubstr(">zero</text>")));
  EXPECT_THAT(svg, Not(HasSubstr("nan")));
  EXPECT_THAT(svg, Not(HasSubstr("inf\"")));
}

TEST(RenderScatterSvgTest, AnEmptyPlotSaysNoData) {
  EXPECT_THAT(RenderScatterSvg(ScatterPlot{}), HasSubstr(">no data</text>"));
}

TEST(RenderScatterGridTest, NestsEachPlotWithItsOwnClipPath) {
  const std::string svg = RenderScatterGrid({TwoPointPlot(), TwoPointPlot(), TwoPointPlot()}, 2);

  EXPECT_THAT(svg, HasSubstr("<svg x=\"640\" y=\"0\" width=\"640\" height=\"440\">"));
  EXPECT_THAT(svg, HasSubstr("<svg x=\"0\" y=\"440\""));
  EXPECT_THAT(svg, HasSubstr("id=\"plot-area-2\""));
  // two columns of 640 and two rows of 440
  EXPECT_THAT(svg, HasSubstr("width=\"1280\" height=\"880\""));
}

}  // namespace
}  // namespace hilrig::host
