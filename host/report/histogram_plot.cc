#include "host/report/histogram_plot.h"

#include <algorithm>
#include <cmath>

#include "host/report/svg_plot.h"

namespace hilrig::host {
namespace {

// Layout: the title, then one legend row, then the plot area; below it the tick labels and the
// x label. Narrower than the time plots: a page shows two of them side by side.
constexpr double kTopPx = 50;
constexpr double kLeftPx = 56;
constexpr double kRightPx = 16;
constexpr double kBelowPx = 40;
constexpr double kLegendBaselinePx = 38;
constexpr double kLegendSwatchPx = 14;
constexpr double kLegendGapPx = 14;
// Counts up to this get the axis 0..kMinCountAxis, whose ticks are whole numbers.
constexpr double kMinCountAxis = 5;
constexpr const char* kLineColor = "#24292F";

struct Frame {
  PlotRect area;
  AxisTicks x, y;

  double X(double value) const {
    return area.left_px + (value - x.lo) / (x.hi - x.lo) * area.width_px;
  }
  double Y(double count) const {
    return area.top_px + (1 - (count - y.lo) / (y.hi - y.lo)) * area.height_px;
  }
  double Bottom() const { return area.top_px + area.height_px; }
  double Right() const { return area.left_px + area.width_px; }
};

int BinCount(const HistogramPlot& plot) { return std::clamp(plot.bins, 1, kMaxHistogramBins); }

std::uint64_t Total(const std::vector<std::uint64_t>& counts) {
  std::uint64_t total = 0;
  for (const std::uint64_t count : counts) total += count;
  return total;
}

// The tallest stack of any bin.
std::uint64_t TallestBin(const HistogramBins& bins) {
  std::uint64_t tallest = 0;
  const std::size_t n = bins.counts.empty() ? 0 : bins.counts.front().size();
  for (std::size_t b = 0; b < n; ++b) {
    std::uint64_t stack = 0;
    for (const auto& group : bins.counts) stack += group[b];
    tallest = std::max(tallest, stack);
  }
  return tallest;
}

Frame FrameOf(const HistogramBins& bins, int width_px, int height_px) {
  Frame frame;
  frame.area = {kLeftPx, kTopPx, width_px - kLeftPx - kRightPx, height_px - kTopPx - kBelowPx};
  frame.x = NiceTicks(bins.lo, bins.hi, TickFit::kTicksWithin);
  frame.x.lo = bins.lo;
  frame.x.hi = bins.hi;
  const double tallest = static_cast<double>(TallestBin(bins));
  frame.y = NiceTicks(0, std::max(tallest, kMinCountAxis), TickFit::kExtendToTicks);
  return frame;
}

std::string GridAndAxes(const Frame& frame) {
  std::string out = "<g class=\"grid\" stroke=\"" + std::string(kSvgGridColor) + "\">\n";
  for (const double v : frame.y.values) {
    out += SvgLine(frame.area.left_px, frame.Y(v), frame.Right(), frame.Y(v), "");
  }
  out += "</g>\n" + SvgFrame(frame.area);
  out += "<g class=\"tick-labels\" fill=\"#333333\">\n";
  for (std::size_t i = 0; i < frame.x.values.size(); ++i) {
    const double x = frame.X(frame.x.values[i]);
    out += SvgLine(x, frame.Bottom(), x, frame.Bottom() + 4, " stroke=\"#333333\"");
    out += SvgText(x, frame.Bottom() + 16, "middle", frame.x.labels[i]);
  }
  for (std::size_t i = 0; i < frame.y.values.size(); ++i) {
    out +=
        SvgText(frame.area.left_px - 6, frame.Y(frame.y.values[i]) + 4, "end", frame.y.labels[i]);
  }
  return out + "</g>\n";
}

std::string Bars(const HistogramPlot& plot, const HistogramBins& bins, const Frame& frame) {
  std::string out = "<g class=\"bars\">\n";
  const int n = BinCount(plot);
  const double width_px = frame.area.width_px / n;
  for (int b = 0; b < n; ++b) {
    const double x = frame.area.left_px + b * width_px;
    std::uint64_t below = 0;
    for (std::size_t g = 0; g < bins.counts.size(); ++g) {
      const std::uint64_t count = bins.counts[g][static_cast<std::size_t>(b)];
      if (count == 0) continue;
      const double top = frame.Y(static_cast<double>(below + count));
      const double bottom = frame.Y(static_cast<double>(below));
      out += "<rect" + SvgAttr("x", SvgPx(x + 0.5)) + SvgAttr("y", SvgPx(top)) +
             SvgAttr("width", SvgPx(std::max(width_px - 1, 1.0))) +
             SvgAttr("height", SvgPx(bottom - top)) +
             SvgAttr("fill", EscapeXmlText(plot.groups[g].color)) + "/>\n";
      below += count;
    }
  }
  return out + "</g>\n";
}

std::string Lines(const HistogramPlot& plot, const Frame& frame) {
  std::string out = "<g class=\"limits\" stroke=\"" + std::string(kLineColor) +
                    "\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\">\n";
  for (const HistogramLine& line : plot.lines) {
    if (!std::isfinite(line.value)) continue;
    const double x = frame.X(line.value);
    out += SvgLine(x, frame.area.top_px, x, frame.Bottom(), "");
  }
  return out + "</g>\n";
}

// The legend on one row under the title: each group with its count, then each line.
std::string Legend(const HistogramPlot& plot, const HistogramBins& bins, const Frame& frame) {
  std::string out = "<g class=\"legend\" fill=\"#222222\">\n";
  double x = frame.area.left_px;
  const auto label = [&](const std::string& text) {
    const auto room = std::max(frame.Right() - x - kLegendSwatchPx - 4, 0.0);
    const std::string shown = SvgTruncated(text, static_cast<std::size_t>(room / kLegendCharPx));
    out += SvgText(x + kLegendSwatchPx + 4, kLegendBaselinePx, "start", shown);
    x += kLegendSwatchPx + 4 + static_cast<double>(shown.size()) * kLegendCharPx + kLegendGapPx;
  };
  for (std::size_t g = 0; g < plot.groups.size(); ++g) {
    if (x >= frame.Right()) break;
    out += SvgSwatch(x, kLegendBaselinePx, kLegendSwatchPx, EscapeXmlText(plot.groups[g].color));
    label(plot.groups[g].name + " (" + std::to_string(Total(bins.counts[g])) + ")");
  }
  for (const HistogramLine& line : plot.lines) {
    if (!std::isfinite(line.value) || x >= frame.Right()) continue;
    out +=
        SvgLine(x, kLegendBaselinePx - 4, x + kLegendSwatchPx, kLegendBaselinePx - 4,
                SvgAttr("stroke", kLineColor) + " stroke-width=\"1.5\" stroke-dasharray=\"5 3\"");
    label(line.name);
  }
  return out + "</g>\n";
}

std::string Note(const HistogramBins& bins, const Frame& frame) {
  std::string text;
  if (!bins.any) {
    text = "no finite value to draw";
  } else if (bins.not_finite > 0) {
    text = std::to_string(bins.not_finite) + " not finite, not drawn";
  }
  if (text.empty()) return "";
  return SvgText(frame.Right() - 4, frame.area.top_px + 14, "end", text,
                 " class=\"note\" fill=\"#777777\"");
}

std::string Labels(const HistogramPlot& plot, const Frame& frame, int width_px) {
  std::string out;
  if (!plot.title.empty()) {
    out += SvgText(width_px / 2.0, 18, "middle", plot.title,
                   " class=\"title\" font-size=\"13\" font-weight=\"bold\"");
  }
  out += SvgText(frame.area.left_px + frame.area.width_px / 2, frame.Bottom() + 32, "middle",
                 plot.x_label, " class=\"x-label\"");
  return out + SvgYLabel(14, frame.area.top_px + frame.area.height_px / 2, "cases");
}

}  // namespace

HistogramBins BinHistogram(const HistogramPlot& plot) {
  HistogramBins bins;
  double lo = 0, hi = 0;
  const auto add = [&](double value) {
    if (!std::isfinite(value)) return;
    lo = bins.any ? std::min(lo, value) : value;
    hi = bins.any ? std::max(hi, value) : value;
    bins.any = true;
  };
  for (const HistogramGroup& group : plot.groups) {
    for (const double value : group.values) add(value);
  }
  const bool values = bins.any;
  for (const HistogramLine& line : plot.lines) add(line.value);
  if (!(hi > lo)) {  // one value (or none): an axis around it, not one lost in rounding
    const double pad = lo == 0 ? 1 : std::abs(lo) * 0.1;
    lo -= pad;
    hi += pad;
  }
  const AxisTicks axis = NiceTicks(lo, hi, TickFit::kExtendToTicks);
  bins.lo = axis.lo;
  bins.hi = axis.hi;
  bins.any = values;
  const int n = BinCount(plot);
  for (const HistogramGroup& group : plot.groups) {
    std::vector<std::uint64_t> counts(static_cast<std::size_t>(n), 0);
    for (const double value : group.values) {
      if (!std::isfinite(value)) {
        ++bins.not_finite;
        continue;
      }
      const double at = std::floor((value - bins.lo) / (bins.hi - bins.lo) * n);
      ++counts[static_cast<std::size_t>(std::clamp(at, 0.0, n - 1.0))];
    }
    bins.counts.push_back(std::move(counts));
  }
  return bins;
}

std::string RenderHistogramSvg(const HistogramPlot& plot) {
  const int width_px = std::clamp(plot.width_px, kMinWidthPx, kMaxSizePx);
  const int height_px = std::clamp(plot.height_px, kMinHeightPx, kMaxSizePx);
  const HistogramBins bins = BinHistogram(plot);
  const Frame frame = FrameOf(bins, width_px, height_px);
  return SvgDocumentStart(width_px, height_px) + GridAndAxes(frame) + Bars(plot, bins, frame) +
         Lines(plot, frame) + Labels(plot, frame, width_px) + Note(bins, frame) +
         Legend(plot, bins, frame) + "</svg>\n";
}

}  // namespace hilrig::host
