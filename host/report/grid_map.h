// Renders a pass map as standalone SVG 1.1 text in the style of svg_plot.h: a grid of cells, one
// per point of two swept axes (a sweep's page, host/sweep/sweep_map.h), the first axis across and
// the second up, each cell filled by the share of its cases that passed, from vermillion (none)
// to blue (all), colours told apart with any colour vision (Okabe-Ito), and written on: "pass" or
// "fail" for a point of one case, "k/n" for a point of several (seeds, scenarios, other axes).
// The axes' values are the tick labels; a legend says what the colours mean. A pure function of
// the description, like RenderSvg: the same description gives byte-identical text. The layout
// constants and functions are public so that tests can compute expected pixels independently.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "host/report/svg_plot.h"

namespace hilrig::host {

struct GridMapCell {
  std::uint64_t passed = 0;
  std::uint64_t cases = 0;  // 0: no case of this point finished (a stopped sweep)
};

struct GridMap {
  std::string title;
  std::string x_label, y_label;      // the axes' names, e.g. "vehicle.mass_kg"
  std::vector<std::string> columns;  // the x tick labels, left to right: one per column
  std::vector<std::string> rows;     // the y tick labels, bottom to top: one per row
  // Row by row from the bottom: column c of row r is cells[r * columns.size() + c]. A cell past
  // the end of the vector has no case.
  std::vector<GridMapCell> cells;
};

inline constexpr const char* kGridMapPassColor = "#0072B2";   // blue: every case passed
inline constexpr const char* kGridMapFailColor = "#D55E00";   // vermillion: no case passed
inline constexpr const char* kGridMapEmptyColor = "#EAEEF2";  // no case finished

// Layout. The cell area sits kGridMapLeftPx from the left (room for the y tick labels and the
// turned y label), kPlotMarginTopPx from the top (the title) and kPlotMarginRightPx from the
// right; below it come kAxisBelowPx of x tick labels and x label, then kLegendGapPx and one
// kLegendRowPx row per legend entry. A cell is kGridMapAreaWidthPx / columns wide and
// kGridMapAreaHeightPx / rows high, each clamped to [kGridMapMinCellPx, kGridMapMaxCellWidthPx]
// and [kGridMapMinCellPx, kGridMapMaxCellHeightPx]; columns and rows that would take the document
// past kMaxSizePx are not drawn, and the legend says how many. The document is at least
// kMinWidthPx wide. Tick labels are cut to kGridMapMaxTickChars characters, and label every
// column_label_step-th column (row_label_step-th row) so that they never overlap; a cell's text
// is drawn when it fits in the cell.
inline constexpr double kGridMapLeftPx = 100;
inline constexpr double kGridMapAreaWidthPx = 560;
inline constexpr double kGridMapAreaHeightPx = 360;
inline constexpr double kGridMapMinCellPx = 14;
inline constexpr double kGridMapMaxCellWidthPx = 80;
inline constexpr double kGridMapMaxCellHeightPx = 44;
inline constexpr std::size_t kGridMapMaxTickChars = 11;

struct GridMapLayout {
  int doc_width_px = 0, doc_height_px = 0;
  PlotRect area;  // the drawn cells, framed
  double cell_width_px = 0, cell_height_px = 0;
  std::size_t drawn_columns = 0, drawn_rows = 0;
  std::size_t column_label_step = 1, row_label_step = 1;
  int legend_rows = 0;
};

GridMapLayout GridMapLayoutOf(const GridMap& map);

// Where the cell of `column` and `row` (0 = the bottom row) is drawn.
PlotRect GridMapCellRect(const GridMapLayout& layout, std::size_t column, std::size_t row);

// A cell's fill: kGridMapPassColor when every case passed, kGridMapFailColor when none did, each
// RGB channel interpolated linearly by the share that passed in between (rounded to the nearest
// integer), kGridMapEmptyColor without a case.
std::string GridMapCellColor(const GridMapCell& cell);

// A cell's text: "pass" or "fail" for one case, "k/n" for more, an en dash for none.
std::string GridMapCellText(const GridMapCell& cell);

// The whole document. Deterministic: the same map gives byte-identical text.
std::string RenderGridMapSvg(const GridMap& map);

}  // namespace hilrig::host
