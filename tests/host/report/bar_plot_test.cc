#include "host/report/bar_plot.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The default 720 px document: the plot area runs from the label column to the right margin.
constexpr double kAreaWidthPx = 720 - kBarLabelColumnPx - kPlotMarginRightPx;

std::size_t Count(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) {
    ++count;
  }
  return count;
}

BarPlot AxesPlot(std::vector<std::string> categories) {
  BarPlot plot;
  plot.title = "max error";
  plot.x_label = "error (N)";
  plot.categories = std::move(categories);
  plot.series = {{"x", "#111111", {}}, {"y", "#222222", {}}, {"z", "#333333", {}}};
  return plot;
}

// "<rect x=.. y=.. width=.. height=.." of a bar from 0 to `width_px` whose top is at `top_px`.
std::string BarRect(double top_px, double width_px) {
  return "<rect x=\"" + SvgPx(kBarLabelColumnPx) + "\" y=\"" + SvgPx(top_px) + "\" width=\"" +
         SvgPx(width_px) + "\" height=\"" + SvgPx(kBarThicknessPx) + "\"";
}

TEST(BarPlotTest, BarLengthsAreTheirValuesOnAnAxisFromZeroToARoundTick) {
  BarPlot plot = AxesPlot({"compensated max", "compensated RMSE"});
  plot.series[0].values = {0.0125, 0.0025};
  plot.series[1].values = {0.025, 0.003};
  plot.series[2].values = {0.005, 0.00625};

  const BarLayout layout = BarLayoutOf(plot);
  // The largest value, 0.025, is a multiple of the 0.005 step: the axis ends on it.
  EXPECT_DOUBLE_EQ(layout.x.lo, 0);
  EXPECT_DOUBLE_EQ(layout.x.hi, 0.025);
  EXPECT_DOUBLE_EQ(layout.area.left_px, kBarLabelColumnPx);
  EXPECT_DOUBLE_EQ(layout.area.width_px, kAreaWidthPx);
  const double band_px = 3 * kBarThicknessPx + kBarCategoryGapPx;
  EXPECT_DOUBLE_EQ(layout.band_px, band_px);

  const std::string svg = RenderBarSvg(plot);
  const double first_top = kPlotMarginTopPx + kBarCategoryGapPx / 2;
  EXPECT_THAT(svg, HasSubstr(BarRect(first_top, kAreaWidthPx / 2)));
  EXPECT_THAT(svg, HasSubstr(BarRect(first_top + kBarThicknessPx, kAreaWidthPx)));
  EXPECT_THAT(svg, HasSubstr(BarRect(first_top + 2 * kBarThicknessPx, kAreaWidthPx / 5)));
  const double second_top = first_top + band_px;
  EXPECT_THAT(svg, HasSubstr(BarRect(second_top, kAreaWidthPx / 10)));
  EXPECT_THAT(svg, HasSubstr(BarRect(second_top + 2 * kBarThicknessPx, kAreaWidthPx / 4)));
  EXPECT_THAT(svg, HasSubstr("fill=\"#333333\"><title>compensated RMSE, z: 0.00625</title>"));

  EXPECT_DOUBLE_EQ(BarValuePx(layout, 0.0125), kBarLabelColumnPx + kAreaWidthPx / 2);
  EXPECT_DOUBLE_EQ(BarTopPx(layout, 1, 2), second_top + 2 * kBarThicknessPx);
}

TEST(BarPlotTest, TheDocumentIsAsTallAsItsRowsAxisAndLegend) {
  BarPlot plot = AxesPlot({"a", "b", "c", "d"});
  plot.references = {{"0.02 N target", 0.02, ""}};

  const BarLayout layout = BarLayoutOf(plot);
  // Four entries in two columns (720 px is wide): two legend rows.
  EXPECT_EQ(layout.legend_columns, kLegendColumnsWide);
  EXPECT_EQ(layout.legend_rows, 2);
  const double area_px = 4 * (3 * kBarThicknessPx + kBarCategoryGapPx);
  EXPECT_DOUBLE_EQ(layout.area.height_px, area_px);
  EXPECT_EQ(layout.doc_height_px,
            static_cast<int>(std::ceil(kPlotMarginTopPx + area_px + kAxisBelowPx + kLegendGapPx +
                                       2 * kLegendRowPx)));
  EXPECT_THAT(RenderBarSvg(plot),
              HasSubstr("height=\"" + std::to_string(layout.doc_height_px) + "\""));
}

TEST(BarPlotTest, AReferenceLineReachesAcrossTheRowsAndWidensTheAxis) {
  BarPlot plot = AxesPlot({"all"});
  plot.series[2].values = {0.012};
  plot.references = {{"0.02 N target", 0.02, "#CF222E"},
                     {"floor", 0.005, ""},
                     {"not drawn", kNaN, ""},
                     {"not drawn either", -1, ""}};

  const BarLayout layout = BarLayoutOf(plot);
  EXPECT_DOUBLE_EQ(layout.x.hi, 0.02);
  const std::string svg = RenderBarSvg(plot);
  const std::string top = SvgPx(kPlotMarginTopPx);
  const std::string bottom = SvgPx(kPlotMarginTopPx + layout.area.height_px);
  const std::string right = SvgPx(kBarLabelColumnPx + kAreaWidthPx);
  EXPECT_THAT(svg, HasSubstr("<line x1=\"" + right + "\" y1=\"" + top + "\" x2=\"" + right +
                             "\" y2=\"" + bottom + "\" stroke=\"#CF222E\""));
  const std::string floor = SvgPx(kBarLabelColumnPx + kAreaWidthPx / 4);
  EXPECT_THAT(svg, HasSubstr("<line x1=\"" + floor + "\" y1=\"" + top + "\" x2=\"" + floor +
                             "\" y2=\"" + bottom + "\" stroke=\"" + kBarReferenceColor + "\""));
  EXPECT_THAT(svg, HasSubstr(">0.02 N target</text>"));
  EXPECT_THAT(svg, HasSubstr(">floor</text>"));
  EXPECT_THAT(svg, Not(HasSubstr("not drawn")));
  // x, y, z and the two drawn lines.
  EXPECT_EQ(layout.legend_rows, 3);
}

TEST(BarPlotTest, AValueWithoutABarIsMarkedNotApplicableAndNeverNaN) {
  BarPlot plot = AxesPlot({"broken"});
  plot.series[0].values = {kNaN};
  plot.series[1].values = {-kInf};
  // z has no value for the category at all.

  const std::string svg = RenderBarSvg(plot);
  EXPECT_EQ(Count(svg, ">n/a</text>"), 3u);
  EXPECT_THAT(svg, Not(HasSubstr("<title>")));  // no bar
  EXPECT_THAT(svg, Not(HasSubstr("nan")));
  EXPECT_THAT(svg, Not(HasSubstr("inf")));
  // Nothing finite: the axis is 0..1 rather than one lost in rounding.
  EXPECT_DOUBLE_EQ(BarLayoutOf(plot).x.hi, 1);

  plot.series[0].values = {0.01};
  plot.series[1].values = {-0.001};
  const std::string one_bar = RenderBarSvg(plot);
  EXPECT_EQ(Count(one_bar, ">n/a</text>"), 2u);
  EXPECT_EQ(Count(one_bar, "<title>"), 1u);
}

TEST(BarPlotTest, SameDescriptionSameBytes) {
  BarPlot plot = AxesPlot({"none", "only chip_noise", "all"});
  for (BarSeries& series : plot.series) series.values = {0.0094, 0.024, 0.0249};
  plot.references = {{"0.02 N target", 0.02, ""}};
  const BarPlot copy = plot;

  EXPECT_EQ(RenderBarSvg(plot), RenderBarSvg(copy));
  EXPECT_EQ(RenderBarSvg(plot), RenderBarSvg(plot));
}

TEST(BarPlotTest, CategoryNamesAreEscapedAndLongOnesCut) {
  const std::string long_name(kBarLabelMaxChars + 10, 'w');
  BarPlot plot = AxesPlot({"a <&> b", long_name});
  plot.title = "t<&>";
  plot.series[0].values = {0.01, 0.01};

  const std::string svg = RenderBarSvg(plot);
  EXPECT_THAT(svg, HasSubstr(">a &lt;&amp;&gt; b</text>"));
  EXPECT_THAT(svg, HasSubstr("<title>a &lt;&amp;&gt; b, x: 0.01</title>"));
  EXPECT_THAT(svg, HasSubstr(">t&lt;&amp;&gt;</text>"));
  EXPECT_THAT(svg, Not(HasSubstr("<&>")));
  EXPECT_THAT(svg, HasSubstr(">" + SvgTruncated(long_name, kBarLabelMaxChars) + "</text>"));
  EXPECT_THAT(svg, Not(HasSubstr(">" + long_name + "</text>")));
}

TEST(BarPlotTest, SeriesWithoutAColourTakeThePalette) {
  BarPlot plot = AxesPlot({"a"});
  for (BarSeries& series : plot.series) {
    series.color.clear();
    series.values = {0.5};
  }
  const std::string svg = RenderBarSvg(plot);
  for (int i = 0; i < 3; ++i) {
    EXPECT_THAT(svg, HasSubstr("fill=\"" + std::string(kSeriesPalette[i]) + "\"><title>"));
  }
}

TEST(BarPlotTest, AnEmptyPlotDrawsItsFrameAndSaysSo) {
  const BarPlot plot;
  const BarLayout layout = BarLayoutOf(plot);
  EXPECT_EQ(layout.legend_rows, 0);
  EXPECT_DOUBLE_EQ(layout.area.height_px, kBarMinAreaPx);
  EXPECT_EQ(layout.doc_height_px,
            static_cast<int>(std::ceil(kPlotMarginTopPx + kBarMinAreaPx + kAxisBelowPx)));
  const std::string svg = RenderBarSvg(plot);
  EXPECT_THAT(svg, HasSubstr("<rect class=\"frame\""));
  EXPECT_THAT(svg, HasSubstr(">no data</text>"));
  EXPECT_THAT(svg, HasSubstr("<g class=\"bars\">\n</g>"));
  EXPECT_THAT(svg, HasSubstr("</svg>\n"));
}

TEST(BarPlotTest, RowsPastTheLargestDocumentAreLeftOutAndCounted) {
  BarPlot plot = AxesPlot(std::vector<std::string>(100000, "row"));
  const BarLayout layout = BarLayoutOf(plot);
  EXPECT_LT(layout.drawn_categories, plot.categories.size());
  EXPECT_GT(layout.drawn_categories, 0u);
  EXPECT_LE(layout.doc_height_px, kMaxSizePx);
  EXPECT_THAT(RenderBarSvg(plot),
              HasSubstr(">" + std::to_string(plot.categories.size() - layout.drawn_categories) +
                        " more rows not drawn</text>"));
}

}  // namespace
}  // namespace hilrig::host
