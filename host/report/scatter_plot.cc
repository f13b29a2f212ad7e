#include "host/report/scatter_plot.h"

#include <algorithm>
#include <cmath>

namespace hilrig::host {
namespace {

constexpr int kMaxLogTicks = 8;
constexpr double kLegendSwatchPx = 24;
constexpr double kMarkerRadiusPx = 3.5;
constexpr const char* kFrontColor = "#333333";

bool Drawable(const ScatterPoint& point) {
  return std::isfinite(point.x) && std::isfinite(point.y) && point.x > 0 && point.y > 0;
}

struct Extent {
  bool any = false;
  double x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0;

  void Add(const ScatterPoint& point) {
    if (!Drawable(point)) return;
    if (!any) {
      x_lo = x_hi = point.x;
      y_lo = y_hi = point.y;
      any = true;
      return;
    }
    x_lo = std::min(x_lo, point.x);
    x_hi = std::max(x_hi, point.x);
    y_lo = std::min(y_lo, point.y);
    y_hi = std::max(y_hi, point.y);
  }
};

Extent ExtentOf(const ScatterPlot& plot) {
  Extent extent;
  for (const ScatterSeries& series : plot.series) {
    for (const ScatterPoint& point : series.points) extent.Add(point);
  }
  for (const ScatterPoint& point : plot.front) extent.Add(point);
  return extent;
}

int HiddenPoints(const ScatterPlot& plot) {
  int hidden = 0;
  for (const ScatterSeries& series : plot.series) {
    hidden +=
        static_cast<int>(std::count_if(series.points.begin(), series.points.end(),
                                       [](const ScatterPoint& point) { return !Drawable(point); }));
  }
  return hidden;
}

std::string DecadeLabel(int exponent) {
  switch (exponent) {
    case -2:
      return "0.01";
    case -1:
      return "0.1";
    case 0:
      return "1";
    case 1:
      return "10";
    case 2:
      return "100";
    case 3:
      return "1000";
    default:
      break;
  }
  return exponent < 0 ? "1e-" + std::to_string(-exponent)
                      : "1e+" + std::string(exponent < 10 ? "0" : "") + std::to_string(exponent);
}

int EntryCount(const ScatterPlot& plot) {
  return static_cast<int>(plot.series.size()) + (plot.front.empty() ? 0 : 1);
}

// The time plot's layout rules (margins, legend rows) for the same size and number of entries.
PlotLayout ScatterLayoutOf(const ScatterPlot& plot) {
  TimePlot shape;
  shape.width_px = plot.width_px;
  shape.height_px = plot.height_px;
  shape.series.resize(static_cast<std::size_t>(EntryCount(plot)));
  return LayoutOf(shape);
}

struct Frame {
  PlotRect area;
  LogAxis x, y;

  double X(double value) const { return LogAxisPx(x, value, area.left_px, area.width_px); }
  double Y(double value) const {
    return area.top_px + area.height_px - LogAxisPx(y, value, 0, area.height_px);
  }
  double Bottom() const { return area.top_px + area.height_px; }
  double Right() const { return area.left_px + area.width_px; }
};

Frame FrameOf(const ScatterPlot& plot, const PlotLayout& layout) {
  const Extent extent = ExtentOf(plot);
  Frame frame;
  frame.area = layout.area;
  frame.x = extent.any ? LogTicks(extent.x_lo, extent.x_hi) : LogTicks(1, 1);
  frame.y = extent.any ? LogTicks(extent.y_lo, extent.y_hi) : LogTicks(1, 1);
  return frame;
}

double Decade(int exponent) { return std::pow(10.0, exponent); }

std::string GridAndAxes(const Frame& frame) {
  std::string grid = "<g class=\"grid\" stroke=\"" + std::string(kSvgGridColor) + "\">\n";
  std::string ticks = "<g class=\"ticks\" stroke=\"#333333\">\n";
  std::string labels = "<g class=\"tick-labels\" fill=\"#333333\">\n";
  for (std::size_t i = 0; i < frame.x.tick_exponents.size(); ++i) {
    const double x = frame.X(Decade(frame.x.tick_exponents[i]));
    grid += SvgLine(x, frame.area.top_px, x, frame.Bottom(), "");
    ticks += SvgLine(x, frame.Bottom(), x, frame.Bottom() + 4, "");
    labels += SvgText(x, frame.Bottom() + 16, "middle", frame.x.labels[i]);
  }
  for (std::size_t i = 0; i < frame.y.tick_exponents.size(); ++i) {
    const double y = frame.Y(Decade(frame.y.tick_exponents[i]));
    grid += SvgLine(frame.area.left_px, y, frame.Right(), y, "");
    ticks += SvgLine(frame.area.left_px - 4, y, frame.area.left_px, y, "");
    labels += SvgText(frame.area.left_px - 6, y + 4, "end", frame.y.labels[i]);
  }
  return grid + "</g>\n" + SvgFrame(frame.area) + ticks + "</g>\n" + labels + "</g>\n";
}

std::string AxisLabels(const ScatterPlot& plot, const Frame& frame, const PlotLayout& layout) {
  return SvgTitle(layout.doc_width_px, plot.title) +
         SvgText(frame.area.left_px + frame.area.width_px / 2, frame.Bottom() + 34, "middle",
                 plot.x_label, " class=\"x-label\"") +
         SvgYLabel(16, frame.area.top_px + frame.area.height_px / 2, plot.y_label);
}

std::string FrontLine(const ScatterPlot& plot, const Frame& frame) {
  std::string points;
  for (const ScatterPoint& point : plot.front) {
    if (!Drawable(point)) continue;
    if (!points.empty()) points += ' ';
    points += SvgPx(frame.X(point.x)) + "," + SvgPx(frame.Y(point.y));
  }
  if (points.empty()) return "";
  return "<polyline class=\"front\" points=\"" + points + "\" fill=\"none\"" +
         SvgAttr("stroke", kFrontColor) + " stroke-width=\"1.2\" stroke-dasharray=\"4 3\"/>\n";
}

std::string Markers(const ScatterSeries& series, const std::string& color, const Frame& frame) {
  std::string out = "<g class=\"points\"" + SvgAttr("fill", color) + " stroke=\"none\">\n";
  std::string labels = "<g class=\"point-labels\" fill=\"#444444\" font-size=\"9\">\n";
  for (const ScatterPoint& point : series.points) {
    if (!Drawable(point)) continue;
    const double x = frame.X(point.x), y = frame.Y(point.y);
    out += "<circle" + SvgAttr("cx", SvgPx(x)) + SvgAttr("cy", SvgPx(y)) +
           SvgAttr("r", SvgPx(kMarkerRadiusPx)) + "/>\n";
    if (!point.label.empty()) labels += SvgText(x + 5, y - 4, "start", point.label);
  }
  return out + "</g>\n" + labels + "</g>\n";
}

struct LegendSlot {
  double x = 0, baseline = 0;
};

LegendSlot SlotOf(int index, const Frame& frame, const PlotLayout& layout) {
  const double column_px = frame.area.width_px / layout.legend_columns;
  const double row_top =
      frame.Bottom() + kAxisBelowPx + kLegendGapPx + (index / layout.legend_columns) * kLegendRowPx;
  return {frame.area.left_px + (index % layout.legend_columns) * column_px, row_top + 12};
}

std::string LegendLabel(const LegendSlot& slot, const std::string& label, const Frame& frame,
                        const PlotLayout& layout) {
  const double column_px = frame.area.width_px / layout.legend_columns;
  const double text_px = std::max(column_px - kLegendSwatchPx - 10, kLegendCharPx * 4);
  return SvgText(slot.x + kLegendSwatchPx + 6, slot.baseline, "start",
                 SvgTruncated(label, static_cast<std::size_t>(text_px / kLegendCharPx)));
}

std::string Legend(const ScatterPlot& plot, const std::vector<std::string>& colors,
                   const Frame& frame, const PlotLayout& layout) {
  if (EntryCount(plot) == 0) return "";
  std::string out = "<g class=\"legend\" fill=\"#222222\">\n";
  int index = 0;
  for (std::size_t i = 0; i < plot.series.size(); ++i, ++index) {
    const LegendSlot slot = SlotOf(index, frame, layout);
    out += "<circle" + SvgAttr("cx", SvgPx(slot.x + kLegendSwatchPx / 2)) +
           SvgAttr("cy", SvgPx(slot.baseline - 4)) + SvgAttr("r", SvgPx(kMarkerRadiusPx)) +
           SvgAttr("fill", colors[i]) + "/>\n";
    out += LegendLabel(slot, plot.series[i].name, frame, layout);
  }
  if (!plot.front.empty()) {
    const LegendSlot slot = SlotOf(index, frame, layout);
    out += SvgLine(slot.x, slot.baseline - 4, slot.x + kLegendSwatchPx, slot.baseline - 4,
                   SvgAttr("stroke", kFrontColor) +
                       " stroke-width=\"1.2\" "
                       "stroke-dasharray=\"4 3\"");
    out += LegendLabel(slot, plot.front_name, frame, layout);
  }
  return out + "</g>\n";
}

std::string Note(const ScatterPlot& plot, const Frame& frame) {
  const int hidden = HiddenPoints(plot);
  std::string text;
  if (!ExtentOf(plot).any) {
    text = "no data";
  } else if (hidden > 0) {
    text = std::to_string(hidden) + (hidden == 1 ? " point" : " points") +
           " not drawn (zero or not finite)";
  }
  if (text.empty()) return "";
  return SvgText(frame.Right() - 4, frame.area.top_px + 14, "end", text,
                 " class=\"note\" fill=\"#777777\"");
}

// The body of one plot (everything inside <svg>), with clip ids made unique by `id`.
std::string Body(const ScatterPlot& plot, const PlotLayout& layout, const std::string& id) {
  const Frame frame = FrameOf(plot, layout);
  const std::vector<std::string> colors = SeriesColors(plot.series);
  const std::string clip_id = "plot-area-" + id;
  std::string out = "<defs><clipPath" + SvgAttr("id", clip_id) + "><rect" +
                    SvgAttr("x", SvgPx(frame.area.left_px - kMarkerRadiusPx)) +
                    SvgAttr("y", SvgPx(frame.area.top_px - kMarkerRadiusPx)) +
                    SvgAttr("width", SvgPx(frame.area.width_px + 2 * kMarkerRadiusPx)) +
                    SvgAttr("height", SvgPx(frame.area.height_px + 2 * kMarkerRadiusPx)) +
                    "/></clipPath></defs>\n";
  out += GridAndAxes(frame);
  out += "<g" + SvgAttr("clip-path", "url(#" + clip_id + ")") + ">\n";
  out += FrontLine(plot, frame);
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    out += Markers(plot.series[i], colors[i], frame);
  }
  out += "</g>\n" + AxisLabels(plot, frame, layout) + Note(plot, frame);
  return out + Legend(plot, colors, frame, layout);
}

}  // namespace

LogAxis LogTicks(double min_value, double max_value) {
  LogAxis axis;
  const bool usable = std::isfinite(min_value) && std::isfinite(max_value) && min_value > 0 &&
                      max_value >= min_value;
  if (usable) {
    axis.lo_exponent = static_cast<int>(std::floor(std::log10(min_value)));
    axis.hi_exponent = static_cast<int>(std::ceil(std::log10(max_value)));
    if (axis.hi_exponent <= axis.lo_exponent) axis.hi_exponent = axis.lo_exponent + 1;
  }
  const int decades = axis.hi_exponent - axis.lo_exponent;
  axis.decade_step = (decades + kMaxLogTicks - 1) / kMaxLogTicks;
  for (int e = axis.lo_exponent; e <= axis.hi_exponent; e += axis.decade_step) {
    axis.tick_exponents.push_back(e);
    axis.labels.push_back(DecadeLabel(e));
  }
  return axis;
}

double LogAxisPx(const LogAxis& axis, double value, double start_px, double length_px) {
  const double lo = axis.lo_exponent, hi = axis.hi_exponent;
  const double position = value > 0 && std::isfinite(value) ? std::log10(value) : lo;
  return start_px + std::clamp((position - lo) / (hi - lo), 0.0, 1.0) * length_px;
}

std::string RenderScatterSvg(const ScatterPlot& plot) {
  const PlotLayout layout = ScatterLayoutOf(plot);
  return SvgDocumentStart(layout.doc_width_px, layout.doc_height_px) + Body(plot, layout, "0") +
         "</svg>\n";
}

std::string RenderScatterGrid(const std::vector<ScatterPlot>& plots, int columns) {
  std::vector<SvgCell> cells;
  for (std::size_t i = 0; i < plots.size(); ++i) {
    const PlotLayout layout = ScatterLayoutOf(plots[i]);
    cells.push_back(
        {layout.doc_width_px, layout.doc_height_px, Body(plots[i], layout, std::to_string(i))});
  }
  return SvgGridDocument(cells, columns);
}

}  // namespace hilrig::host
