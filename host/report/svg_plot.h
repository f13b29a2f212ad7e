// Renders the time plots of a run report (force and position against time, with the envelopes
// drawn as allowed regions) as standalone SVG 1.1 text. RenderSvg is a pure function of the plot
// description: no files, no clock, no locale, so the same description always gives byte-identical
// text and a run's plots are as reproducible as its trace. The layout constants, the tick choice
// and the decimation are public so that tests can compute expected pixels independently.
#pragma once

#include <cstddef>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "host/report/xml_text.h"

namespace hilrig::host {

struct PlotSeries {
  std::string name;            // legend label, e.g. "grasp force (true)"
  std::vector<double> time_s;  // same length as value; a non-finite time is a gap too
  std::vector<double> value;   // NaN / Inf = a gap in the line
  std::string color;           // CSS colour; empty = the next colour of kSeriesPalette
  bool dashed = false;
  // A wide, light line drawn under a thin one of the same colour keeps both visible where they
  // agree (a true force under its estimate).
  double stroke_px = 1.5;
  double opacity = 1;  // in (0, 1]
};

// Something that happened at one time (a grasp command, a set-point, a gust): a grey vertical
// line across the plot with its label at the top.
struct PlotMarker {
  double time_s = 0;
  std::string label;
};

// An envelope: the allowed region over a time window.
struct PlotBand {
  std::string name;                    // legend label, e.g. "envelope grasp_force"
  std::optional<double> lower, upper;  // at least one; a non-finite limit counts as absent
  double from_s = 0;
  double until_s = std::numeric_limits<double>::infinity();  // clipped to the plotted time range
  bool expect_fail = false;  // an ablation's envelope: drawn red dashed, said so in the legend
};

struct TimePlot {
  std::string title;
  std::string y_label;  // with unit, e.g. "force (N)"; the unit in parentheses labels band limits
  std::vector<PlotSeries> series;
  std::vector<PlotBand> bands;
  std::vector<PlotMarker> markers;  // those outside the plotted time range are left out
  // The horizontal axis: time unless a plot puts another quantity in the series' time_s (a top
  // view puts x there), in which case equal_scale gives both axes the same units per pixel.
  std::string x_label = "time (s)";
  bool equal_scale = false;
  int width_px = 900, height_px = 360;       // clamped to [kMinWidthPx or kMinHeightPx, kMaxSizePx]
  std::size_t max_points_per_series = 2000;  // longer series are min/max decimated
};

// The whole SVG document. Deterministic: the same plot gives byte-identical text.
std::string RenderSvg(const TimePlot& plot);

// Several plots in one document, `columns` per row (at least 1), each in its own nested <svg>
// with its own axes (small multiples: each pad, each axis at its own scale).
std::string RenderSvgGrid(const std::vector<TimePlot>& plots, int columns);

// One cell of a grid of plots: a plot's document body (without the header and the closing tag)
// and its size.
struct SvgCell {
  int width_px = 0, height_px = 0;
  std::string body;
};

// The cells laid out `columns` per row (at least 1) in cells as large as the largest.
std::string SvgGridDocument(const std::vector<SvgCell>& cells, int columns);

// Okabe-Ito colours (colour-blind safe), handed in order to series without a colour. Green is
// last because allowed bands are green.
inline constexpr const char* kSeriesPalette[] = {"#0072B2", "#D55E00", "#CC79A7", "#E69F00",
                                                 "#56B4E9", "#000000", "#009E73"};

// Layout. The plot area sits kPlotMarginLeftPx from the left, kPlotMarginTopPx from the top and
// kPlotMarginRightPx from the right; below it come kAxisBelowPx of tick labels and x label, then
// (if there are entries) kLegendGapPx and one kLegendRowPx row per legend row. Legend entries
// (series first, then bands) fill kLegendColumnsWide columns when the document is at least
// kLegendWideFromPx wide, else one. If that leaves less than kMinPlotHeightPx for the plot, the
// document grows taller instead.
inline constexpr double kPlotMarginLeftPx = 72;
inline constexpr double kPlotMarginRightPx = 24;
inline constexpr double kPlotMarginTopPx = 36;
inline constexpr double kAxisBelowPx = 44;
inline constexpr double kLegendGapPx = 6;
// The average glyph width of an 11 px label, for fitting legend text into a column.
inline constexpr double kLegendCharPx = 6.2;
inline constexpr double kLegendRowPx = 16;
inline constexpr int kLegendColumnsWide = 2;
inline constexpr int kLegendWideFromPx = 600;
inline constexpr double kMinPlotHeightPx = 100;
inline constexpr int kMinWidthPx = 320;
inline constexpr int kMinHeightPx = 200;
inline constexpr int kMaxSizePx = 20000;

struct PlotRect {
  double left_px = 0, top_px = 0, width_px = 0, height_px = 0;
};

struct PlotLayout {
  int doc_width_px = 0, doc_height_px = 0;
  PlotRect area;  // the axes frame; every mark is drawn inside it
  int legend_columns = 1, legend_rows = 0;
};

PlotLayout LayoutOf(const TimePlot& plot);

// kExtendToTicks widens the axis to the enclosing multiples of the step (the time axis ends on a
// round time); kTicksWithin keeps the axis as given and labels the multiples inside it (the value
// axis keeps its 5 % padding without wasting a whole step).
enum class TickFit { kExtendToTicks, kTicksWithin };

struct AxisTicks {
  double lo = 0, hi = 1;       // the axis range after fitting
  double step = 0;             // 1, 2 or 5 x 10^k
  std::vector<double> values;  // ascending, at most 8 (at least 4 unless the range is odd)
  std::vector<std::string>
      labels;  // fixed decimals from the step: "0.3", never 0.30000000000000004
};

// Needs finite lo < hi; anything else gets a fallback axis around what is usable (never NaN).
AxisTicks NiceTicks(double lo, double hi, TickFit fit);

struct PlotPoint {
  double time_s = 0, value = 0;  // both NaN for a gap marker
};

// Reduces a series to at most 2 x max(1, max_points / 2) finite points (plus gap markers) when it
// is longer than max_points: equal-count index buckets each keep their min and max in sample
// order, so a one-sample spike survives. Shorter series come back unchanged. Samples with a
// non-finite time or value become gap markers; lengths are cut to the shorter of the two.
std::vector<PlotPoint> DecimateMinMax(const std::vector<double>& time_s,
                                      const std::vector<double>& value, std::size_t max_points);

// Building blocks for other plot kinds (host/report/scatter_plot.h) drawn in the same style:
// locale-free numbers, escaped text, the document header, the frame, title, y label and legend
// swatches. Each is what RenderSvg itself uses.
inline constexpr const char* kSvgGridColor = "#E3E3E3";

// A pixel coordinate with two decimals; never "nan", "inf" or "-0" (non-finite gives "0").
std::string SvgPx(double value);

// ` name="value"`; `value` must already be escaped.
std::string SvgAttr(std::string_view name, const std::string& value);

// A <line> element; `extra` is appended raw inside the tag (attributes).
std::string SvgLine(double x1, double y1, double x2, double y2, const std::string& extra);

// A <text> element; `raw_text` is escaped here, `extra` is appended raw inside the tag.
std::string SvgText(double x, double y, const std::string& anchor, const std::string& raw_text,
                    const std::string& extra = "");

// The XML declaration, the opening <svg> of a width x height document and its white background.
std::string SvgDocumentStart(int width_px, int height_px);

// `text` cut to at most `max_chars` UTF-8 characters, the last one an ellipsis when cut.
std::string SvgTruncated(const std::string& text, std::size_t max_chars);

// The axes frame: an unfilled <rect> around `area` in the axes' colour.
std::string SvgFrame(const PlotRect& area);

// The plot's title, bold, centred over a document `doc_width_px` wide; "" when `title` is empty.
std::string SvgTitle(int doc_width_px, const std::string& title);

// A y axis label centred on (x, y), turned to read upwards.
std::string SvgYLabel(double x, double y, const std::string& label);

// A legend's colour swatch: a <rect> `width_px` wide and 10 px high standing on `baseline` + 1;
// `color` must already be escaped, `extra` is appended raw inside the tag.
std::string SvgSwatch(double x, double baseline, double width_px, const std::string& color,
                      const std::string& extra = "");

// Each series' colour, escaped for an attribute: its own `color`, or for a series without one the
// next colour of kSeriesPalette in turn. `Series` is any series type with a `color` string.
template <typename Series>
std::vector<std::string> SeriesColors(const std::vector<Series>& series) {
  std::vector<std::string> colors;
  std::size_t next_palette_index = 0;
  for (const Series& one : series) {
    colors.push_back(EscapeXmlText(
        one.color.empty() ? kSeriesPalette[next_palette_index++ % std::size(kSeriesPalette)]
                          : one.color));
  }
  return colors;
}

}  // namespace hilrig::host
