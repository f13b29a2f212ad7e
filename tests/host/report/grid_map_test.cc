// The pass map of two swept axes: each cell at the pixels the documented layout gives, filled by
// the share of its cases that passed, with its count written on it, the axes' values as tick
// labels, every text escaped, and a grid too large for a document cut with a remark.
#include "host/report/grid_map.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::size_t Count(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) {
    ++count;
  }
  return count;
}

// "<rect x=.. y=.. width=.. height=.. fill=..": a cell's rectangle as the map writes it.
std::string CellRect(double x_px, double y_px, double width_px, double height_px,
                     const std::string& fill) {
  return "<rect x=\"" + SvgPx(x_px) + "\" y=\"" + SvgPx(y_px) + "\" width=\"" + SvgPx(width_px) +
         "\" height=\"" + SvgPx(height_px) + "\" fill=\"" + fill + "\">";
}

// Three masses across, two bounds up, three seeds a point; the top right point never finished.
GridMap SeedsMap() {
  GridMap map;
  map.title = "cases passed";
  map.x_label = "vehicle.mass_kg";
  map.y_label = "envelopes[1].upper";
  map.columns = {"0.5", "0.6", "0.7"};
  map.rows = {"1e-09", "1"};
  map.cells = {{3, 3}, {1, 3}, {0, 3},   // the bottom row
               {2, 3}, {3, 3}, {0, 0}};  // the top row
  return map;
}

TEST(GridMapTest, CellsSitWhereTheLayoutPutsThemFilledByTheShareThatPassed) {
  const GridMap map = SeedsMap();
  const GridMapLayout layout = GridMapLayoutOf(map);
  // 560 / 3 and 360 / 2 are past the largest cell: 80 x 44 px cells, from the left margin.
  EXPECT_DOUBLE_EQ(layout.cell_width_px, kGridMapMaxCellWidthPx);
  EXPECT_DOUBLE_EQ(layout.cell_height_px, kGridMapMaxCellHeightPx);
  EXPECT_DOUBLE_EQ(layout.area.left_px, kGridMapLeftPx);
  EXPECT_DOUBLE_EQ(layout.area.top_px, kPlotMarginTopPx);
  EXPECT_DOUBLE_EQ(layout.area.width_px, 3 * 80);
  EXPECT_DOUBLE_EQ(layout.area.height_px, 2 * 44);
  EXPECT_EQ(layout.doc_width_px, 100 + 240 + 24);
  // Below the cells: the axis band, the gap, and four legend rows (pass, fail, share, none).
  EXPECT_EQ(layout.legend_rows, 4);
  EXPECT_EQ(layout.doc_height_px, 36 + 88 + 44 + 6 + 4 * 16);

  const std::string svg = RenderGridMapSvg(map);
  const double left = kGridMapLeftPx, top = kPlotMarginTopPx;
  // The bottom row is the lower one; the fills blend vermillion (213, 94, 0) into blue
  // (0, 114, 178) by the share: 1/3 is (142, 100.7, 59.3), 2/3 is (71, 107.3, 118.7), rounded.
  EXPECT_THAT(svg, HasSubstr(CellRect(left, top + 44, 80, 44, "#0072B2")));
  EXPECT_THAT(svg, HasSubstr(CellRect(left + 80, top + 44, 80, 44, "#8E653B")));
  EXPECT_THAT(svg, HasSubstr(CellRect(left + 160, top + 44, 80, 44, "#D55E00")));
  EXPECT_THAT(svg, HasSubstr(CellRect(left, top, 80, 44, "#476B77")));
  EXPECT_THAT(svg, HasSubstr(CellRect(left + 80, top, 80, 44, "#0072B2")));
  EXPECT_THAT(svg, HasSubstr(CellRect(left + 160, top, 80, 44, kGridMapEmptyColor)));
  EXPECT_EQ(Count(svg, "<title>"), 6u);
  EXPECT_THAT(svg, HasSubstr("<title>vehicle.mass_kg = 0.6, envelopes[1].upper = 1e-09: 1 of 3 "
                             "cases passed</title>"));
  EXPECT_THAT(svg, HasSubstr("envelopes[1].upper = 1: no case finished</title>"));

  // Each count at its cell's centre, white on blue, black on vermillion and on grey.
  EXPECT_THAT(svg, HasSubstr("<text x=\"220.00\" y=\"106.00\" text-anchor=\"middle\" "
                             "fill=\"#FFFFFF\">1/3</text>"));
  EXPECT_THAT(svg, HasSubstr("<text x=\"300.00\" y=\"106.00\" text-anchor=\"middle\" "
                             "fill=\"#000000\">0/3</text>"));
  EXPECT_THAT(svg, HasSubstr("<text x=\"300.00\" y=\"62.00\" text-anchor=\"middle\" "
                             "fill=\"#000000\">\xE2\x80\x93</text>"));
  // The axes' values under the columns' and beside the rows' centres.
  EXPECT_THAT(svg, HasSubstr("<text x=\"140.00\" y=\"140.00\" text-anchor=\"middle\">0.5</text>"));
  EXPECT_THAT(svg, HasSubstr("<text x=\"94.00\" y=\"106.00\" text-anchor=\"end\">1e-09</text>"));
  EXPECT_THAT(svg, HasSubstr("<text x=\"94.00\" y=\"62.00\" text-anchor=\"end\">1</text>"));
  EXPECT_THAT(svg, HasSubstr("class=\"x-label\">vehicle.mass_kg</text>"));
  EXPECT_THAT(svg, HasSubstr("class=\"y-label\" transform=\"rotate(-90 16.00 80.00)\">"
                             "envelopes[1].upper</text>"));
  EXPECT_THAT(svg, HasSubstr(">every case passed</text>"));
  EXPECT_THAT(svg, HasSubstr(">k/n: k of the n cases passed</text>"));
  EXPECT_THAT(svg, HasSubstr(">no case finished</text>"));
  EXPECT_EQ(RenderGridMapSvg(map), svg);
}

TEST(GridMapTest, ACellsColourGoesFromVermillionToBlueByTheShareThatPassed) {
  EXPECT_EQ(GridMapCellColor({1, 1}), kGridMapPassColor);
  EXPECT_EQ(GridMapCellColor({0, 1}), kGridMapFailColor);
  EXPECT_EQ(GridMapCellColor({0, 0}), kGridMapEmptyColor);
  EXPECT_EQ(GridMapCellColor({1, 2}), "#6B6859");          // (106.5, 104, 89): halves round up
  EXPECT_EQ(GridMapCellColor({5, 4}), kGridMapPassColor);  // more passes than cases: all passed
  EXPECT_EQ(GridMapCellText({1, 1}), "pass");
  EXPECT_EQ(GridMapCellText({0, 1}), "fail");
  EXPECT_EQ(GridMapCellText({2, 5}), "2/5");
  EXPECT_EQ(GridMapCellText({0, 0}), "\xE2\x80\x93");
}

TEST(GridMapTest, APointOfOneCaseReadsPassOrFailAndTheLegendSaysSo) {
  GridMap map;
  map.x_label = "a";
  map.y_label = "b";
  map.columns = {"1", "2"};
  map.rows = {"3", "4"};
  map.cells = {{1, 1}, {0, 1}, {1, 1}, {1, 1}};
  const std::string svg = RenderGridMapSvg(map);
  EXPECT_EQ(Count(svg, ">pass</text>"), 3u);
  EXPECT_EQ(Count(svg, ">fail</text>"), 1u);
  EXPECT_THAT(svg, HasSubstr(">passed</text>"));
  EXPECT_THAT(svg, HasSubstr(">failed</text>"));
  EXPECT_THAT(svg, Not(HasSubstr("k/n")));
  EXPECT_THAT(svg, Not(HasSubstr("no case finished")));
  EXPECT_EQ(GridMapLayoutOf(map).legend_rows, 2);
}

TEST(GridMapTest, EveryTextIsEscaped) {
  GridMap map = SeedsMap();
  map.title = "hover <fast> & slow";
  map.x_label = "a<b";
  map.y_label = "\"q\"";
  map.columns[0] = "x&y";
  map.rows[1] = "<1>";
  const std::string svg = RenderGridMapSvg(map);
  EXPECT_THAT(svg, HasSubstr(">hover &lt;fast&gt; &amp; slow</text>"));
  EXPECT_THAT(svg, HasSubstr(">a&lt;b</text>"));
  EXPECT_THAT(svg, HasSubstr(">&quot;q&quot;</text>"));
  EXPECT_THAT(svg, HasSubstr(">x&amp;y</text>"));
  EXPECT_THAT(svg, HasSubstr(">&lt;1&gt;</text>"));
  EXPECT_THAT(svg, HasSubstr("<title>a&lt;b = x&amp;y, &quot;q&quot; = 1e-09: 3 of 3"));
  EXPECT_THAT(svg, Not(HasSubstr("<b")));
  EXPECT_THAT(svg, Not(HasSubstr("<1>")));
}

// 2000 columns of the smallest cell do not fit a 20000 px document: the rest are counted, the
// cells are too small for their text, and the tick labels skip columns rather than overlap.
TEST(GridMapTest, AGridTooWideForADocumentIsCutAndSaysHowManyColumnsAreLeftOut) {
  GridMap map;
  map.x_label = "x";
  map.y_label = "y";
  map.rows = {"0", "1"};
  for (int i = 0; i < 2000; ++i) {
    map.columns.push_back(std::to_string(i));
    map.cells.push_back({1, 1});
  }
  const GridMapLayout layout = GridMapLayoutOf(map);
  EXPECT_DOUBLE_EQ(layout.cell_width_px, kGridMapMinCellPx);
  const auto fitting = static_cast<std::size_t>((kMaxSizePx - kGridMapLeftPx - kPlotMarginRightPx) /
                                                kGridMapMinCellPx);
  EXPECT_EQ(layout.drawn_columns, fitting);
  EXPECT_LE(layout.doc_width_px, kMaxSizePx);
  EXPECT_GT(layout.column_label_step, 1u);
  const std::string svg = RenderGridMapSvg(map);
  EXPECT_THAT(svg, HasSubstr(">" + std::to_string(2000 - fitting) + " more columns not drawn<"));
  EXPECT_THAT(svg, Not(HasSubstr(">pass</text>")));
  // The second row has no cells in the vector: no case there.
  EXPECT_THAT(svg, HasSubstr(">no case finished</text>"));
}

TEST(GridMapTest, AMapWithoutPointsStillMakesADocumentThatSaysSo) {
  GridMap map;
  map.x_label = "x";
  map.y_label = "y";
  const std::string svg = RenderGridMapSvg(map);
  EXPECT_THAT(svg, HasSubstr("<svg xmlns=\"http://www.w3.org/2000/svg\""));
  EXPECT_THAT(svg, HasSubstr(">no grid point to draw</text>"));
  EXPECT_THAT(svg, Not(HasSubstr("<title>")));
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

}  // namespace
}  // namespace hilrig::host
