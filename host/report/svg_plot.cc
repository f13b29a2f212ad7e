#include "host/report/svg_plot.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <string_view>

namespace hilrig::host {
namespace {

constexpr double kMaxFinite = std::numeric_limits<double>::max();
constexpr int kMaxTicks = 8;
constexpr double kTickTolerance = 1e-9;  // in steps: 0.3 / 0.1 must count as 3, not 2.999...
constexpr double kPaddingFraction = 0.05;
constexpr double kLegendSwatchPx = 24;
constexpr const char* kBandColor = "#009E73";
constexpr const char* kFailBandColor = "#C00000";
constexpr const char* kGridColor = kSvgGridColor;
constexpr const char* kEnDash = "\xE2\x80\x93";
constexpr const char* kEllipsis = "\xE2\x80\xA6";

// ---------------------------------------------------------------------------------------------
// Numbers: locale-free and never "nan" or "inf", so output is stable and always valid SVG.

std::string ToChars(double value, std::chars_format format, int precision) {
  if (!std::isfinite(value)) return "0";
  if (value == 0) value = 0;  // no "-0"
  std::array<char, 400> buffer{};
  auto [end, error] =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), value, format, precision);
  if (error != std::errc()) return "0";
  return std::string(buffer.data(), end);
}

std::string Px(double value) { return ToChars(value, std::chars_format::fixed, 2); }

std::string Int(int value) { return std::to_string(value); }

// Band limits in the legend: as the user wrote them, short ("0.25", "1e+06").
std::string Compact(double value) { return ToChars(value, std::chars_format::general, 6); }

// ---------------------------------------------------------------------------------------------
// Ranges.

double Half(double value) { return value * 0.5; }  // exact, and never overflows a difference

// Half of hi - lo, finite for any finite lo, hi.
double HalfSpan(double lo, double hi) { return Half(hi) - Half(lo); }

double Fraction(double value, double lo, double hi) {
  const double half_span = HalfSpan(lo, hi);
  if (!(half_span > 0)) return 0.5;
  return std::clamp((Half(value) - Half(lo)) / half_span, 0.0, 1.0);
}

struct Range {
  double lo = 0, hi = 1;
};

Range Widened(double value) {
  const double half = value == 0 ? 1.0 : std::max(std::abs(value) * 0.1, 1e-300);
  return {std::max(value - half, -kMaxFinite), std::min(value + half, kMaxFinite)};
}

Range Padded(Range range) {
  const double pad = 2 * kPaddingFraction * HalfSpan(range.lo, range.hi);
  return {std::max(range.lo - pad, -kMaxFinite), std::min(range.hi + pad, kMaxFinite)};
}

struct Extent {
  bool any = false;
  double lo = kMaxFinite, hi = -kMaxFinite;

  void Add(double value) {
    if (!std::isfinite(value)) return;
    any = true;
    lo = std::min(lo, value);
    hi = std::max(value, hi);
  }
  Range ToRange() const {
    if (!any) return {0, 1};
    return lo < hi ? Range{lo, hi} : Widened(lo);
  }
};

std::size_t SampleCount(const PlotSeries& series) {
  return std::min(series.time_s.size(), series.value.size());
}

std::optional<double> FiniteOrNone(const std::optional<double>& limit) {
  if (limit && std::isfinite(*limit)) return limit;
  return std::nullopt;
}

Extent TimeExtent(const TimePlot& plot) {
  Extent extent;
  for (const PlotSeries& series : plot.series) {
    for (std::size_t i = 0; i < SampleCount(series); ++i) extent.Add(series.time_s[i]);
  }
  if (extent.any) return extent;
  for (const PlotBand& band : plot.bands) {
    extent.Add(band.from_s);
    extent.Add(band.until_s);
  }
  return extent;
}

bool HasFiniteData(const TimePlot& plot) {
  for (const PlotSeries& series : plot.series) {
    for (std::size_t i = 0; i < SampleCount(series); ++i) {
      if (std::isfinite(series.time_s[i]) && std::isfinite(series.value[i])) return true;
    }
  }
  return false;
}

Extent ValueExtent(const TimePlot& plot) {
  Extent extent;
  for (const PlotSeries& series : plot.series) {
    for (std::size_t i = 0; i < SampleCount(series); ++i) {
      if (std::isfinite(series.time_s[i])) extent.Add(series.value[i]);
    }
  }
  for (const PlotBand& band : plot.bands) {
    if (auto lower = FiniteOrNone(band.lower)) extent.Add(*lower);
    if (auto upper = FiniteOrNone(band.upper)) extent.Add(*upper);
  }
  return extent;
}

// ---------------------------------------------------------------------------------------------
// Ticks.

struct Step {
  int mantissa = 1;  // 1, 2 or 5
  int exponent = 0;  // step = mantissa x 10^exponent, exponent >= -303 so 10^-exponent is finite

  double Scale(double value) const {  // value / step
    return exponent < 0 ? value * std::pow(10.0, -exponent) / mantissa
                        : value / std::pow(10.0, exponent) / mantissa;
  }
  double Tick(double k) const {  // k x step, rounded once so 3 x 0.1 is 0.3
    return exponent < 0 ? k * mantissa / std::pow(10.0, -exponent)
                        : k * mantissa * std::pow(10.0, exponent);
  }
  Step Next() const {
    if (mantissa == 1) return {2, exponent};
    if (mantissa == 2) return {5, exponent};
    return {1, exponent + 1};
  }
};

struct TickIndices {
  double first = 0, last = 0;
  double Count() const { return last - first + 1; }
};

TickIndices IndicesFor(Step step, double lo, double hi, TickFit fit) {
  const double lo_steps = step.Scale(lo), hi_steps = step.Scale(hi);
  if (fit == TickFit::kExtendToTicks) {
    return {std::floor(lo_steps + kTickTolerance), std::ceil(hi_steps - kTickTolerance)};
  }
  return {std::ceil(lo_steps - kTickTolerance), std::floor(hi_steps + kTickTolerance)};
}

std::vector<std::string> TickLabels(const std::vector<double>& values, Step step) {
  double largest = 0;
  for (double value : values) largest = std::max(largest, std::abs(value));
  const bool fixed = largest < 1e7 && step.exponent >= -6;
  const int decimals = std::max(0, -step.exponent);
  const int digits =
      largest > 0
          ? std::clamp(static_cast<int>(std::floor(std::log10(largest))) - step.exponent + 1, 1, 17)
          : 1;
  std::vector<std::string> labels;
  for (double value : values) {
    labels.push_back(fixed ? ToChars(value, std::chars_format::fixed, decimals)
                           : ToChars(value, std::chars_format::general, digits));
  }
  return labels;
}

// A finite lo < hi whose span is not lost in rounding, so steps and ticks stay finite.
Range Usable(double lo, double hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return {0, 1};
  if (hi < lo) std::swap(lo, hi);
  const double mid = Half(lo) + Half(hi);
  const double min_half = std::max(std::abs(mid) * 1e-12, 1e-300);
  if (HalfSpan(lo, hi) >= min_half) return {lo, hi};
  return {std::max(mid - min_half, -kMaxFinite), std::min(mid + min_half, kMaxFinite)};
}

}  // namespace

AxisTicks NiceTicks(double lo_in, double hi_in, TickFit fit) {
  const Range range = Usable(lo_in, hi_in);
  Step step{1, static_cast<int>(std::floor(std::log10(HalfSpan(range.lo, range.hi)))) - 2};
  step.exponent = std::max(step.exponent, -303);
  TickIndices indices = IndicesFor(step, range.lo, range.hi, fit);
  while (indices.Count() > kMaxTicks) {
    step = step.Next();
    indices = IndicesFor(step, range.lo, range.hi, fit);
  }
  AxisTicks ticks;
  ticks.step = step.Tick(1);
  ticks.lo = range.lo;
  ticks.hi = range.hi;
  if (fit == TickFit::kExtendToTicks) {
    // Near the end of the double range a whole step may not fit; then the axis ends at the data.
    const double lo = step.Tick(indices.first), hi = step.Tick(indices.last);
    if (std::isfinite(lo)) ticks.lo = std::min(lo, range.lo);
    if (std::isfinite(hi)) ticks.hi = std::max(hi, range.hi);
  }
  for (double k = indices.first; k <= indices.last; ++k) {
    const double value = step.Tick(k);
    if (std::isfinite(value) && value >= ticks.lo - ticks.step * kTickTolerance &&
        value <= ticks.hi + ticks.step * kTickTolerance) {
      ticks.values.push_back(value == 0 ? 0.0 : value);
    }
  }
  ticks.labels = TickLabels(ticks.values, step);
  return ticks;
}

std::vector<PlotPoint> DecimateMinMax(const std::vector<double>& time_s,
                                      const std::vector<double>& value, std::size_t max_points) {
  const std::size_t n = std::min(time_s.size(), value.size());
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const auto finite = [&](std::size_t i) {
    return std::isfinite(time_s[i]) && std::isfinite(value[i]);
  };
  const auto point = [&](std::size_t i) {
    return finite(i) ? PlotPoint{time_s[i], value[i]} : PlotPoint{kNaN, kNaN};
  };
  std::vector<PlotPoint> out;
  if (n <= max_points) {
    for (std::size_t i = 0; i < n; ++i) out.push_back(point(i));
    return out;
  }
  const std::size_t buckets = std::max<std::size_t>(1, max_points / 2);
  const std::size_t base = n / buckets, extra = n % buckets;
  std::size_t begin = 0;
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::size_t end = begin + base + (b < extra ? 1 : 0);
    std::optional<std::size_t> lowest, highest, first_gap;
    for (std::size_t i = begin; i < end; ++i) {
      if (!finite(i)) {
        if (!first_gap) first_gap = i;
        continue;
      }
      if (!lowest || value[i] < value[*lowest]) lowest = i;
      if (!highest || value[i] > value[*highest]) highest = i;
    }
    std::vector<std::size_t> keep;
    for (const auto& index : {lowest, highest, first_gap}) {
      if (index) keep.push_back(*index);
    }
    std::sort(keep.begin(), keep.end());
    keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
    for (std::size_t i : keep) out.push_back(point(i));
    begin = end;
  }
  return out;
}

PlotLayout LayoutOf(const TimePlot& plot) {
  PlotLayout layout;
  layout.doc_width_px = std::clamp(plot.width_px, kMinWidthPx, kMaxSizePx);
  const int requested_height = std::clamp(plot.height_px, kMinHeightPx, kMaxSizePx);
  layout.legend_columns = layout.doc_width_px >= kLegendWideFromPx ? kLegendColumnsWide : 1;
  const std::size_t entries = plot.series.size() + plot.bands.size();
  const std::size_t columns = static_cast<std::size_t>(layout.legend_columns);
  layout.legend_rows = static_cast<int>((entries + columns - 1) / columns);
  const double legend_px =
      layout.legend_rows > 0 ? kLegendGapPx + layout.legend_rows * kLegendRowPx : 0;
  const double below_px = kAxisBelowPx + legend_px;
  const double plot_height =
      std::max(requested_height - kPlotMarginTopPx - below_px, kMinPlotHeightPx);
  layout.doc_height_px = static_cast<int>(std::ceil(kPlotMarginTopPx + plot_height + below_px));
  layout.area = {kPlotMarginLeftPx, kPlotMarginTopPx,
                 layout.doc_width_px - kPlotMarginLeftPx - kPlotMarginRightPx, plot_height};
  return layout;
}

namespace {

// ---------------------------------------------------------------------------------------------
// Drawing.

struct Frame {
  PlotRect area;
  AxisTicks x, y;

  double X(double time_s) const {
    return area.left_px + Fraction(time_s, x.lo, x.hi) * area.width_px;
  }
  double Y(double value) const {
    return area.top_px + (1 - Fraction(value, y.lo, y.hi)) * area.height_px;
  }
  double Right() const { return area.left_px + area.width_px; }
  double Bottom() const { return area.top_px + area.height_px; }
};

// Widens the axis with fewer units per pixel about its middle until both have the same, so that a
// top view keeps its shapes.
void EqualScale(Frame& frame) {
  const double x_per_px = (frame.x.hi - frame.x.lo) / frame.area.width_px;
  const double y_per_px = (frame.y.hi - frame.y.lo) / frame.area.height_px;
  if (!(std::isfinite(x_per_px) && std::isfinite(y_per_px) && x_per_px > 0 && y_per_px > 0)) return;
  AxisTicks& narrow = x_per_px < y_per_px ? frame.x : frame.y;
  const double length_px = x_per_px < y_per_px ? frame.area.width_px : frame.area.height_px;
  const double half = std::max(x_per_px, y_per_px) * length_px / 2;
  const double middle = narrow.lo / 2 + narrow.hi / 2;
  narrow = NiceTicks(middle - half, middle + half, TickFit::kTicksWithin);
}

Frame FrameOf(const TimePlot& plot, const PlotLayout& layout) {
  Frame frame;
  frame.area = layout.area;
  const Range time = TimeExtent(plot).ToRange();
  frame.x = NiceTicks(time.lo, time.hi, TickFit::kExtendToTicks);
  const Extent values = ValueExtent(plot);
  const Range value = values.any ? Padded(values.ToRange()) : Range{0, 1};
  frame.y = NiceTicks(value.lo, value.hi, TickFit::kTicksWithin);
  if (plot.equal_scale) EqualScale(frame);
  return frame;
}

std::string Attr(std::string_view name, const std::string& value) {
  std::string out;  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on chained operator+
  out.reserve(name.size() + value.size() + 4);
  out.append(" ").append(name).append("=\"").append(value).append("\"");
  return out;
}

std::string Line(double x1, double y1, double x2, double y2, const std::string& extra) {
  return "<line" + Attr("x1", Px(x1)) + Attr("y1", Px(y1)) + Attr("x2", Px(x2)) +
         Attr("y2", Px(y2)) + extra + "/>\n";
}

std::string Text(double x, double y, const std::string& anchor, const std::string& raw_text,
                 const std::string& extra = "") {
  return "<text" + Attr("x", Px(x)) + Attr("y", Px(y)) + Attr("text-anchor", anchor) + extra + ">" +
         EscapeXmlText(raw_text) + "</text>\n";
}

std::string Grid(const Frame& frame) {
  std::string out = "<g class=\"grid\" stroke=\"" + std::string(kGridColor) + "\">\n";
  for (double t : frame.x.values) {
    out += Line(frame.X(t), frame.area.top_px, frame.X(t), frame.Bottom(), "");
  }
  for (double v : frame.y.values) {
    out += Line(frame.area.left_px, frame.Y(v), frame.Right(), frame.Y(v), "");
  }
  return out + "</g>\n";
}

std::string Axes(const Frame& frame) {
  std::string out = SvgFrame(frame.area);
  out += "<g class=\"ticks\" stroke=\"#333333\">\n";
  for (double t : frame.x.values)
    out += Line(frame.X(t), frame.Bottom(), frame.X(t), frame.Bottom() + 4, "");
  for (double v : frame.y.values) {
    out += Line(frame.area.left_px - 4, frame.Y(v), frame.area.left_px, frame.Y(v), "");
  }
  out += "</g>\n<g class=\"tick-labels\" fill=\"#333333\">\n";
  for (std::size_t i = 0; i < frame.x.values.size(); ++i) {
    out += Text(frame.X(frame.x.values[i]), frame.Bottom() + 16, "middle", frame.x.labels[i]);
  }
  for (std::size_t i = 0; i < frame.y.values.size(); ++i) {
    out += Text(frame.area.left_px - 6, frame.Y(frame.y.values[i]) + 4, "end", frame.y.labels[i]);
  }
  return out + "</g>\n";
}

std::string Labels(const TimePlot& plot, const Frame& frame, const PlotLayout& layout) {
  std::string out = SvgTitle(layout.doc_width_px, plot.title);
  out += Text(frame.area.left_px + frame.area.width_px / 2, frame.Bottom() + 34, "middle",
              plot.x_label, " class=\"x-label\"");
  if (!plot.y_label.empty()) {
    out += SvgYLabel(16, frame.area.top_px + frame.area.height_px / 2, plot.y_label);
  }
  return out;
}

// Bands.

struct BandStyle {
  std::string color, dash, fill_opacity;
};

BandStyle StyleOf(const PlotBand& band) {
  if (band.expect_fail) return {kFailBandColor, " stroke-dasharray=\"5 3\"", "0.08"};
  return {kBandColor, "", "0.15"};
}

// The band's window on the time axis, or nothing when it does not overlap the plot.
std::optional<Range> BandWindow(const PlotBand& band, const AxisTicks& x) {
  if (std::isnan(band.from_s) || std::isnan(band.until_s)) return std::nullopt;
  const double from = std::max(band.from_s, x.lo), until = std::min(band.until_s, x.hi);
  if (!(from < until)) return std::nullopt;
  return Range{from, until};
}

std::string Band(const PlotBand& band, const Frame& frame) {
  const auto lower = FiniteOrNone(band.lower), upper = FiniteOrNone(band.upper);
  const auto window = BandWindow(band, frame.x);
  if (!window || (!lower && !upper)) return "";
  const BandStyle style = StyleOf(band);
  const double x1 = frame.X(window->lo), x2 = frame.X(window->hi);
  std::string out = "<g class=\"" + std::string(band.expect_fail ? "band-fail" : "band") + "\">\n";
  if (!(lower && upper && *lower > *upper)) {  // an empty band has no allowed region to fill
    const double top = upper ? frame.Y(*upper) : frame.area.top_px;
    const double bottom = lower ? frame.Y(*lower) : frame.Bottom();
    out += "<rect" + Attr("x", Px(x1)) + Attr("y", Px(top)) + Attr("width", Px(x2 - x1)) +
           Attr("height", Px(bottom - top)) + Attr("fill", style.color) +
           Attr("fill-opacity", style.fill_opacity) + "/>\n";
  }
  const std::string stroke = Attr("stroke", style.color) + " stroke-width=\"1.2\"" + style.dash;
  for (const auto& limit : {lower, upper}) {
    if (limit) out += Line(x1, frame.Y(*limit), x2, frame.Y(*limit), stroke);
  }
  return out + "</g>\n";
}

// Series.

std::string SeriesColor(const PlotSeries& series, std::size_t& next_palette_index) {
  if (!series.color.empty()) return series.color;
  constexpr std::size_t kPaletteSize = std::size(kSeriesPalette);
  return kSeriesPalette[next_palette_index++ % kPaletteSize];
}

double StrokeWidthPx(const PlotSeries& series) {
  return std::isfinite(series.stroke_px) ? std::clamp(series.stroke_px, 0.5, 12.0) : 1.5;
}

double DotRadiusPx(const PlotSeries& series) { return std::max(1.5, StrokeWidthPx(series) / 2); }

// A lone point is a dot as wide as the series' line (at least 3 px across).
std::string Run(const std::vector<std::string>& points, const std::string& color,
                double dot_radius_px) {
  if (points.empty()) return "";
  if (points.size() == 1) {  // a lone sample between gaps would vanish as a polyline
    const std::size_t comma = points[0].find(',');
    return "<circle" + Attr("cx", points[0].substr(0, comma)) +
           Attr("cy", points[0].substr(comma + 1)) + Attr("r", Compact(dot_radius_px)) +
           Attr("fill", color) + " stroke=\"none\"/>\n";
  }
  std::string out = "<polyline points=\"";
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i > 0) out += ' ';
    out += points[i];
  }
  return out + "\"/>\n";
}

// The series' width, opacity and dash pattern as attributes (its line and its legend swatch).
std::string StrokeStyle(const PlotSeries& series) {
  const double width_px = StrokeWidthPx(series);
  const double opacity = std::isfinite(series.opacity) ? std::clamp(series.opacity, 0.1, 1.0) : 1;
  std::string out = Attr("stroke-width", Compact(width_px));
  if (opacity < 1) out += Attr("stroke-opacity", Compact(opacity));
  if (series.dashed) out += " stroke-dasharray=\"6 3\"";
  return out;
}

// Markers.

std::string Truncated(const std::string& text, std::size_t max_chars);

// A grey dashed line per marker in the time range under the series, and its label at the top of
// the plot over them; labels of neighbouring markers go on kMarkerLabelRows rows in turn so that
// close events stay readable.
constexpr int kMarkerLabelRows = 3;
constexpr const char* kMarkerColor = "#777777";

std::vector<const PlotMarker*> ShownMarkers(const TimePlot& plot, const Frame& frame) {
  std::vector<const PlotMarker*> shown;
  for (const PlotMarker& marker : plot.markers) {
    if (std::isfinite(marker.time_s) && marker.time_s >= frame.x.lo &&
        marker.time_s <= frame.x.hi) {
      shown.push_back(&marker);
    }
  }
  return shown;
}

std::string MarkerLines(const TimePlot& plot, const Frame& frame) {
  const std::vector<const PlotMarker*> shown = ShownMarkers(plot, frame);
  if (shown.empty()) return "";
  std::string out =
      "<g class=\"markers\"" + Attr("stroke", kMarkerColor) + " stroke-dasharray=\"2 3\">\n";
  for (const PlotMarker* marker : shown) {
    const double x = frame.X(marker->time_s);
    out += Line(x, frame.area.top_px, x, frame.Bottom(), "");
  }
  return out + "</g>\n";
}

std::string MarkerLabels(const TimePlot& plot, const Frame& frame) {
  const std::vector<const PlotMarker*> shown = ShownMarkers(plot, frame);
  if (shown.empty()) return "";
  // A white outline under each letter keeps the label readable over the lines it crosses.
  std::string out = "<g class=\"marker-labels\"" + Attr("fill", kMarkerColor) +
                    " font-size=\"10\" stroke=\"#FFFFFF\" stroke-width=\"3\" "
                    "paint-order=\"stroke\">\n";
  for (std::size_t i = 0; i < shown.size(); ++i) {
    const double y = frame.area.top_px + 11 + 11 * static_cast<double>(i % kMarkerLabelRows);
    out += Text(frame.X(shown[i]->time_s) + 3, y, "start", Truncated(shown[i]->label, 40));
  }
  return out + "</g>\n";
}

std::string Series(const PlotSeries& series, const std::string& raw_color, const Frame& frame,
                   std::size_t max_points) {
  const std::string color = EscapeXmlText(raw_color);
  std::string out = "<g class=\"series\" fill=\"none\"" + Attr("stroke", color) +
                    StrokeStyle(series) + " stroke-linejoin=\"round\">\n";
  std::vector<std::string> run;
  for (const PlotPoint& p : DecimateMinMax(series.time_s, series.value, max_points)) {
    if (std::isnan(p.value)) {
      out += Run(run, color, DotRadiusPx(series));
      run.clear();
      continue;
    }
    std::string xy = Px(frame.X(p.time_s)) + "," + Px(frame.Y(p.value));
    if (run.empty() || run.back() != xy) run.push_back(std::move(xy));
  }
  out += Run(run, color, DotRadiusPx(series));
  return out + "</g>\n";
}

// Legend.

std::string UnitOf(const std::string& y_label) {
  const std::size_t open = y_label.rfind('(');
  if (open == std::string::npos) return "";
  const std::size_t close = y_label.find(')', open);
  if (close == std::string::npos || close == open + 1) return "";
  return y_label.substr(open + 1, close - open - 1);
}

std::string WithUnit(double value, const std::string& unit) {
  return Compact(value) + (unit.empty() ? "" : " " + unit);
}

std::string BandLabel(const PlotBand& band, const std::string& unit) {
  const auto lower = FiniteOrNone(band.lower), upper = FiniteOrNone(band.upper);
  std::string label = (band.name.empty() ? "envelope" : band.name) + ": ";
  if (lower && upper) {
    label += Compact(*lower) + kEnDash + WithUnit(*upper, unit);
    if (*lower > *upper) label += " (empty: lower > upper)";
  } else if (lower) {
    label += "\xE2\x89\xA5 " + WithUnit(*lower, unit);
  } else if (upper) {
    label += "\xE2\x89\xA4 " + WithUnit(*upper, unit);
  } else {
    label += "no limits";
  }
  if (std::isnan(band.from_s) || std::isnan(band.until_s)) {
    label += " (bad time window)";
  } else if (std::isfinite(band.until_s)) {
    label += " over " + Compact(band.from_s) + kEnDash + Compact(band.until_s) + " s";
  } else if (band.from_s != 0) {
    label += " from " + Compact(band.from_s) + " s";
  }
  if (band.expect_fail) label += " (expected to fail)";
  return label;
}

std::string SeriesLabel(const PlotSeries& series, std::size_t index) {
  std::string label = series.name.empty() ? "series " + std::to_string(index + 1) : series.name;
  if (series.time_s.size() != series.value.size()) {
    label += " (lengths differ: " + std::to_string(series.time_s.size()) + " times, " +
             std::to_string(series.value.size()) + " values)";
  }
  return label;
}

bool IsUtf8Continuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

// Cuts at a UTF-8 character boundary so a long label stays in its column.
std::string Truncated(const std::string& text, std::size_t max_chars) {
  const auto chars = static_cast<std::size_t>(
      std::count_if(text.begin(), text.end(), [](char c) { return !IsUtf8Continuation(c); }));
  if (chars <= max_chars || max_chars < 2) return text;
  std::size_t kept = 0, cut = 0;
  while (cut < text.size() && (kept < max_chars - 1 || IsUtf8Continuation(text[cut]))) {
    kept += !IsUtf8Continuation(text[cut]);
    ++cut;
  }
  return text.substr(0, cut) + kEllipsis;
}

struct LegendSlot {
  double x = 0, baseline = 0;
};

LegendSlot SlotOf(std::size_t index, const Frame& frame, const PlotLayout& layout) {
  const std::size_t columns = static_cast<std::size_t>(layout.legend_columns);
  const double column_px = frame.area.width_px / layout.legend_columns;
  const double row_top =
      frame.Bottom() + kAxisBelowPx + kLegendGapPx + (index / columns) * kLegendRowPx;
  return {frame.area.left_px + (index % columns) * column_px, row_top + 12};
}

std::string LegendText(const LegendSlot& slot, const std::string& label, const PlotLayout& layout,
                       const Frame& frame) {
  const double column_px = frame.area.width_px / layout.legend_columns;
  const double text_px = std::max(column_px - kLegendSwatchPx - 10, kLegendCharPx * 4);
  const auto max_chars = static_cast<std::size_t>(text_px / kLegendCharPx);
  return Text(slot.x + kLegendSwatchPx + 6, slot.baseline, "start", Truncated(label, max_chars));
}

// A legend swatch is at least 2 px wide so that a thin line's colour shows.
std::string LegendStrokeStyle(PlotSeries series) {
  series.stroke_px = std::max(series.stroke_px, 2.0);
  return StrokeStyle(series);
}

std::string Legend(const TimePlot& plot, const std::vector<std::string>& colors, const Frame& frame,
                   const PlotLayout& layout) {
  if (plot.series.empty() && plot.bands.empty()) return "";
  std::string out = "<g class=\"legend\" fill=\"#222222\">\n";
  std::size_t index = 0;
  for (std::size_t i = 0; i < plot.series.size(); ++i, ++index) {
    const LegendSlot slot = SlotOf(index, frame, layout);
    const PlotSeries& series = plot.series[i];
    out += Line(slot.x, slot.baseline - 4, slot.x + kLegendSwatchPx, slot.baseline - 4,
                Attr("stroke", EscapeXmlText(colors[i])) + LegendStrokeStyle(series));
    out += LegendText(slot, SeriesLabel(series, i), layout, frame);
  }
  const std::string unit = UnitOf(plot.y_label);
  for (const PlotBand& band : plot.bands) {
    const LegendSlot slot = SlotOf(index++, frame, layout);
    const BandStyle style = StyleOf(band);
    out += SvgSwatch(
        slot.x, slot.baseline, kLegendSwatchPx, style.color,
        Attr("fill-opacity", style.fill_opacity) + Attr("stroke", style.color) + style.dash);
    out += LegendText(slot, BandLabel(band, unit), layout, frame);
  }
  return out + "</g>\n";
}

std::string Header(const PlotLayout& layout) {
  const std::string w = Int(layout.doc_width_px), h = Int(layout.doc_height_px);
  return "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n"
         "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\"" +
         Attr("width", w) + Attr("height", h) + Attr("viewBox", "0 0 " + w + " " + h) +
         " font-family=\"sans-serif\" font-size=\"11\">\n" + "<rect" + Attr("width", w) +
         Attr("height", h) + " fill=\"#FFFFFF\"/>\n";
}

std::string ClipPath(const PlotRect& area, const std::string& id) {
  return "<defs><clipPath" + Attr("id", id) + "><rect" + Attr("x", Px(area.left_px)) +
         Attr("y", Px(area.top_px)) + Attr("width", Px(area.width_px)) +
         Attr("height", Px(area.height_px)) + "/></clipPath></defs>\n";
}

// Everything of one plot's document after its header; `clip_id` names its clip path, unique in
// the document.
std::string Body(const TimePlot& plot, const PlotLayout& layout, const std::string& clip_id) {
  const Frame frame = FrameOf(plot, layout);
  std::vector<std::string> colors;
  std::size_t next_palette_index = 0;
  for (const PlotSeries& series : plot.series) {
    colors.push_back(SeriesColor(series, next_palette_index));
  }

  std::string out = ClipPath(frame.area, clip_id) + Grid(frame);
  out += "<g clip-path=\"url(#" + clip_id + ")\">\n";
  for (const PlotBand& band : plot.bands) out += Band(band, frame);
  out += MarkerLines(plot, frame);
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    out += Series(plot.series[i], colors[i], frame, plot.max_points_per_series);
  }
  out += MarkerLabels(plot, frame);
  out += "</g>\n" + Axes(frame) + Labels(plot, frame, layout);
  if (!HasFiniteData(plot)) {
    out += Text(frame.area.left_px + frame.area.width_px / 2,
                frame.area.top_px + frame.area.height_px / 2, "middle", "no data",
                " class=\"note\" fill=\"#777777\" font-size=\"14\"");
  }
  return out + Legend(plot, colors, frame, layout);
}

}  // namespace

std::string RenderSvg(const TimePlot& plot) {
  const PlotLayout layout = LayoutOf(plot);
  return Header(layout) + Body(plot, layout, "plot-area") + "</svg>\n";
}

std::string RenderSvgGrid(const std::vector<TimePlot>& plots, int columns) {
  std::vector<SvgCell> cells;
  for (std::size_t i = 0; i < plots.size(); ++i) {
    const PlotLayout layout = LayoutOf(plots[i]);
    cells.push_back({layout.doc_width_px, layout.doc_height_px,
                     Body(plots[i], layout, "plot-area-" + std::to_string(i))});
  }
  return SvgGridDocument(cells, columns);
}

std::string SvgGridDocument(const std::vector<SvgCell>& cells, int columns) {
  columns = std::max(columns, 1);
  int cell_width = kMinWidthPx, cell_height = kMinHeightPx;
  for (const SvgCell& cell : cells) {
    cell_width = std::max(cell_width, cell.width_px);
    cell_height = std::max(cell_height, cell.height_px);
  }
  const int count = static_cast<int>(cells.size());
  const int used_columns = std::max(1, std::min(columns, count));
  const int rows = std::max(1, (count + columns - 1) / columns);
  std::string out = SvgDocumentStart(used_columns * cell_width, rows * cell_height);
  for (int i = 0; i < count; ++i) {
    const SvgCell& cell = cells[static_cast<std::size_t>(i)];
    out += "<svg" + Attr("x", std::to_string((i % columns) * cell_width)) +
           Attr("y", std::to_string((i / columns) * cell_height)) +
           Attr("width", std::to_string(cell.width_px)) +
           Attr("height", std::to_string(cell.height_px)) + ">\n" + cell.body + "</svg>\n";
  }
  return out + "</svg>\n";
}

std::string SvgPx(double value) { return Px(value); }

std::string SvgAttr(std::string_view name, const std::string& value) { return Attr(name, value); }

std::string SvgLine(double x1, double y1, double x2, double y2, const std::string& extra) {
  return Line(x1, y1, x2, y2, extra);
}

std::string SvgText(double x, double y, const std::string& anchor, const std::string& raw_text,
                    const std::string& extra) {
  return Text(x, y, anchor, raw_text, extra);
}

std::string SvgDocumentStart(int width_px, int height_px) {
  PlotLayout layout;
  layout.doc_width_px = width_px;
  layout.doc_height_px = height_px;
  return Header(layout);
}

std::string SvgTruncated(const std::string& text, std::size_t max_chars) {
  return Truncated(text, max_chars);
}

std::string SvgFrame(const PlotRect& area) {
  return "<rect class=\"frame\"" + Attr("x", Px(area.left_px)) + Attr("y", Px(area.top_px)) +
         Attr("width", Px(area.width_px)) + Attr("height", Px(area.height_px)) +
         " fill=\"none\" stroke=\"#333333\"/>\n";
}

std::string SvgTitle(int doc_width_px, const std::string& title) {
  if (title.empty()) return "";
  return Text(doc_width_px / 2.0, 22, "middle", title,
              " class=\"title\" font-size=\"14\" font-weight=\"bold\"");
}

std::string SvgYLabel(double x, double y, const std::string& label) {
  return Text(x, y, "middle", label,
              " class=\"y-label\" transform=\"rotate(-90 " + Px(x) + " " + Px(y) + ")\"");
}

std::string SvgSwatch(double x, double baseline, double width_px, const std::string& color,
                      const std::string& extra) {
  return "<rect" + Attr("x", Px(x)) + Attr("y", Px(baseline - 9)) + Attr("width", Px(width_px)) +
         " height=\"10\"" + Attr("fill", color) + extra + "/>\n";
}

}  // namespace hilrig::host
