// Renders horizontal grouped bar charts as standalone SVG 1.1 text, in the style of svg_plot.h:
// one row per category (the force-error pages, host/report/accuracy_page.h, draw a condition or
// a budget configuration per row), one bar per series in each row (an axis x, y, z), every bar
// starting at 0, and vertical reference lines (a target, a floor) drawn dashed across the rows.
// A pure function of the description, like RenderSvg: the same description gives byte-identical
// text. A value that is not finite or is negative has no bar: a small "n/a" stands in its place,
// so a broken figure never puts NaN into the picture. The layout constants and functions are
// public so that tests can compute expected pixels independently.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "host/report/svg_plot.h"

namespace hilrig::host {

struct BarSeries {
  std::string name;            // legend label, e.g. "z"
  std::string color;           // CSS colour; empty = the next colour of kSeriesPalette
  std::vector<double> values;  // one per category; missing, non-finite or negative: "n/a"
};

// A vertical line across the rows at `value`, e.g. a target; left out when not finite or negative.
struct BarReference {
  std::string name;   // legend label, e.g. "0.02 N target"
  double value = 0;   // in the x axis' unit
  std::string color;  // CSS colour; empty = kBarReferenceColor
};

struct BarPlot {
  std::string title;
  std::string x_label;                  // with unit, e.g. "max error (N)"
  std::vector<std::string> categories;  // one row each, top to bottom
  std::vector<BarSeries> series;        // drawn in this order within each row, top to bottom
  std::vector<BarReference> references;
  int width_px = 720;  // clamped to [kMinWidthPx, kMaxSizePx]; the height follows the rows
};

inline constexpr const char* kBarReferenceColor = "#24292F";

// Layout. The category labels fill a column kBarLabelColumnPx wide left of the plot area, cut to
// kBarLabelMaxChars characters; the area sits kPlotMarginTopPx from the top (the title above it)
// and kPlotMarginRightPx from the right. Each drawn category is a band of one kBarThicknessPx bar
// per series (at least one) and kBarCategoryGapPx, half above and half below its bars. Below the
// area come kAxisBelowPx of tick labels and x label, then the legend (series, then references) in
// svg_plot.h's rows and columns. Categories past kMaxSizePx of document are not drawn, and the
// plot says how many; an area with no category is kBarMinAreaPx high.
inline constexpr double kBarLabelColumnPx = 200;
inline constexpr std::size_t kBarLabelMaxChars =
    static_cast<std::size_t>((kBarLabelColumnPx - 12) / kLegendCharPx);
inline constexpr double kBarThicknessPx = 8;
inline constexpr double kBarCategoryGapPx = 10;
inline constexpr double kBarMinAreaPx = 60;

struct BarLayout {
  int doc_width_px = 0, doc_height_px = 0;
  PlotRect area;
  AxisTicks x;         // from 0 to a round tick at or above the largest value and reference
  double band_px = 0;  // the height of one category's band
  std::size_t drawn_categories = 0;
  int legend_columns = 1, legend_rows = 0;
};

BarLayout BarLayoutOf(const BarPlot& plot);

// The pixel x of `value` on the layout's axis, clamped to the area; a value the axis cannot show
// (not finite, negative) is at the axis' 0.
double BarValuePx(const BarLayout& layout, double value);

// The top of the bar of `series` (0-based) in `category`'s band.
double BarTopPx(const BarLayout& layout, std::size_t category, std::size_t series);

// Whether `value` gets a bar: finite and at least 0.
bool BarDrawable(double value);

// The whole document. Deterministic: the same plot gives byte-identical text.
std::string RenderBarSvg(const BarPlot& plot);

}  // namespace hilrig::host
