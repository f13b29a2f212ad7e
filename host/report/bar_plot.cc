#include "host/report/bar_plot.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "host/report/xml_text.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

constexpr double kLegendSwatchPx = 24;
constexpr const char* kAxisColor = "#333333";
constexpr const char* kMutedColor = "#777777";
constexpr const char* kReferenceDash = " stroke-width=\"1.5\" stroke-dasharray=\"5 3\"";

bool ReferenceDrawn(const BarReference& reference) { return BarDrawable(reference.value); }

std::size_t DrawnReferences(const BarPlot& plot) {
  return static_cast<std::size_t>(
      std::count_if(plot.references.begin(), plot.references.end(), ReferenceDrawn));
}

// The value of `series` in `category`, NaN (no bar) where the series has none.
double ValueOf(const BarSeries& series, std::size_t category) {
  return category < series.values.size() ? series.values[category]
                                         : std::numeric_limits<double>::quiet_NaN();
}

// The largest value the axis must reach: every drawn bar and every reference line.
double LargestValue(const BarPlot& plot, std::size_t drawn_categories) {
  double largest = 0;
  for (const BarSeries& series : plot.series) {
    for (std::size_t c = 0; c < drawn_categories; ++c) {
      const double value = ValueOf(series, c);
      if (BarDrawable(value)) largest = std::max(largest, value);
    }
  }
  for (const BarReference& reference : plot.references) {
    if (ReferenceDrawn(reference)) largest = std::max(largest, reference.value);
  }
  return largest;
}

struct Frame {
  const BarLayout& layout;

  double X(double value) const { return BarValuePx(layout, value); }
  double Left() const { return layout.area.left_px; }
  double Top() const { return layout.area.top_px; }
  double Right() const { return layout.area.left_px + layout.area.width_px; }
  double Bottom() const { return layout.area.top_px + layout.area.height_px; }
};

std::string GridAndAxes(const Frame& frame) {
  const AxisTicks& x = frame.layout.x;
  std::string grid = "<g class=\"grid\" stroke=\"" + std::string(kSvgGridColor) + "\">\n";
  std::string ticks = "<g class=\"ticks\" stroke=\"" + std::string(kAxisColor) + "\">\n";
  std::string labels = "<g class=\"tick-labels\" fill=\"" + std::string(kAxisColor) + "\">\n";
  for (std::size_t i = 0; i < x.values.size(); ++i) {
    const double px = frame.X(x.values[i]);
    grid += SvgLine(px, frame.Top(), px, frame.Bottom(), "");
    ticks += SvgLine(px, frame.Bottom(), px, frame.Bottom() + 4, "");
    labels += SvgText(px, frame.Bottom() + 16, "middle", x.labels[i]);
  }
  return grid + "</g>\n" + SvgFrame(frame.layout.area) + ticks + "</g>\n" + labels + "</g>\n";
}

std::string CategoryLabels(const BarPlot& plot, const Frame& frame) {
  std::string out = "<g class=\"categories\" fill=\"#222222\">\n";
  for (std::size_t c = 0; c < frame.layout.drawn_categories; ++c) {
    const double middle = frame.Top() + (static_cast<double>(c) + 0.5) * frame.layout.band_px;
    out += SvgText(frame.Left() - 6, middle + 4, "end",
                   SvgTruncated(plot.categories[c], kBarLabelMaxChars));
  }
  return out + "</g>\n";
}

// The bars, each with its exact value as a tooltip, and an "n/a" where a value has no bar.
std::string Bars(const BarPlot& plot, const std::vector<std::string>& colors, const Frame& frame) {
  std::string bars = "<g class=\"bars\">\n";
  std::string missing = "<g class=\"n-a\"" + SvgAttr("fill", kMutedColor) + " font-size=\"9\">\n";
  const double zero_px = frame.X(0);
  for (std::size_t c = 0; c < frame.layout.drawn_categories; ++c) {
    for (std::size_t s = 0; s < plot.series.size(); ++s) {
      const double top = BarTopPx(frame.layout, c, s);
      const double value = ValueOf(plot.series[s], c);
      if (!BarDrawable(value)) {
        missing += SvgText(zero_px + 3, top + kBarThicknessPx, "start", "n/a");
        continue;
      }
      const std::string tip =
          plot.categories[c] + ", " + plot.series[s].name + ": " + rig::NumberText(value);
      bars += "<rect" + SvgAttr("x", SvgPx(zero_px)) + SvgAttr("y", SvgPx(top)) +
              SvgAttr("width", SvgPx(frame.X(value) - zero_px)) +
              SvgAttr("height", SvgPx(kBarThicknessPx)) + SvgAttr("fill", colors[s]) + "><title>" +
              EscapeXmlText(tip) + "</title></rect>\n";
    }
  }
  return bars + "</g>\n" + missing + "</g>\n";
}

std::string ReferenceColor(const BarReference& reference) {
  return EscapeXmlText(reference.color.empty() ? kBarReferenceColor : reference.color);
}

std::string ReferenceLines(const BarPlot& plot, const Frame& frame) {
  std::string out = "<g class=\"references\">\n";
  for (const BarReference& reference : plot.references) {
    if (!ReferenceDrawn(reference)) continue;
    const double x = frame.X(reference.value);
    out += SvgLine(x, frame.Top(), x, frame.Bottom(),
                   SvgAttr("stroke", ReferenceColor(reference)) + kReferenceDash);
  }
  return out + "</g>\n";
}

std::string Labels(const BarPlot& plot, const Frame& frame) {
  return SvgTitle(frame.layout.doc_width_px, plot.title) +
         SvgText((frame.Left() + frame.Right()) / 2, frame.Bottom() + 34, "middle", plot.x_label,
                 " class=\"x-label\"");
}

// The legend in svg_plot.h's slots: series swatches, then each drawn reference's dashed line.
std::string Legend(const BarPlot& plot, const std::vector<std::string>& colors,
                   const Frame& frame) {
  const BarLayout& layout = frame.layout;
  if (layout.legend_rows == 0) return "";
  const double column_px = layout.area.width_px / layout.legend_columns;
  const auto text_chars = static_cast<std::size_t>(
      std::max(column_px - kLegendSwatchPx - 10, kLegendCharPx * 4) / kLegendCharPx);
  std::string out = "<g class=\"legend\" fill=\"#222222\">\n";
  int index = 0;
  const auto entry = [&](auto draw_swatch, const std::string& label) {
    const double x = frame.Left() + (index % layout.legend_columns) * column_px;
    const double baseline = frame.Bottom() + kAxisBelowPx + kLegendGapPx +
                            (index / layout.legend_columns) * kLegendRowPx + 12;
    out += draw_swatch(x, baseline);
    out += SvgText(x + kLegendSwatchPx + 6, baseline, "start", SvgTruncated(label, text_chars));
    ++index;
  };
  for (std::size_t s = 0; s < plot.series.size(); ++s) {
    entry([&](double x,
              double baseline) { return SvgSwatch(x, baseline, kLegendSwatchPx, colors[s]); },
          plot.series[s].name);
  }
  for (const BarReference& reference : plot.references) {
    if (!ReferenceDrawn(reference)) continue;
    entry(
        [&](double x, double baseline) {
          return SvgLine(x, baseline - 4, x + kLegendSwatchPx, baseline - 4,
                         SvgAttr("stroke", ReferenceColor(reference)) + kReferenceDash);
        },
        reference.name);
  }
  return out + "</g>\n";
}

// Says how many categories the document had no room for, or that there is nothing to draw.
std::string Remark(const BarPlot& plot, const Frame& frame) {
  std::string text;
  if (plot.categories.empty()) {
    text = "no data";
  } else if (frame.layout.drawn_categories < plot.categories.size()) {
    text = std::to_string(plot.categories.size() - frame.layout.drawn_categories) +
           " more rows not drawn";
  }
  if (text.empty()) return "";
  return SvgText(frame.Right() - 4, frame.Top() + 14, "end", text,
                 " class=\"remark\"" + SvgAttr("fill", kMutedColor));
}

}  // namespace

bool BarDrawable(double value) { return std::isfinite(value) && value >= 0; }

BarLayout BarLayoutOf(const BarPlot& plot) {
  BarLayout layout;
  layout.doc_width_px = std::clamp(plot.width_px, kMinWidthPx, kMaxSizePx);
  layout.legend_columns = layout.doc_width_px >= kLegendWideFromPx ? kLegendColumnsWide : 1;
  const std::size_t entries = plot.series.size() + DrawnReferences(plot);
  const auto columns = static_cast<std::size_t>(layout.legend_columns);
  layout.legend_rows = static_cast<int>((entries + columns - 1) / columns);
  const double legend_px =
      layout.legend_rows > 0 ? kLegendGapPx + layout.legend_rows * kLegendRowPx : 0;
  const double fixed_px = kPlotMarginTopPx + kAxisBelowPx + legend_px;
  layout.band_px =
      static_cast<double>(std::max<std::size_t>(plot.series.size(), 1)) * kBarThicknessPx +
      kBarCategoryGapPx;
  const double room_px = std::max(kMaxSizePx - fixed_px, 0.0);
  layout.drawn_categories =
      std::min(plot.categories.size(), static_cast<std::size_t>(room_px / layout.band_px));
  const double area_height_px = layout.drawn_categories > 0
                                    ? static_cast<double>(layout.drawn_categories) * layout.band_px
                                    : kBarMinAreaPx;
  layout.doc_height_px = static_cast<int>(std::ceil(fixed_px + area_height_px));
  layout.area = {kBarLabelColumnPx, kPlotMarginTopPx,
                 layout.doc_width_px - kBarLabelColumnPx - kPlotMarginRightPx, area_height_px};
  const double largest = LargestValue(plot, layout.drawn_categories);
  layout.x = NiceTicks(0, largest > 0 ? largest : 1, TickFit::kExtendToTicks);
  return layout;
}

double BarValuePx(const BarLayout& layout, double value) {
  const double shown = BarDrawable(value) ? value : 0;
  const double span = layout.x.hi - layout.x.lo;
  const double fraction = span > 0 ? std::clamp((shown - layout.x.lo) / span, 0.0, 1.0) : 0;
  return layout.area.left_px + fraction * layout.area.width_px;
}

double BarTopPx(const BarLayout& layout, std::size_t category, std::size_t series) {
  return layout.area.top_px + static_cast<double>(category) * layout.band_px +
         kBarCategoryGapPx / 2 + static_cast<double>(series) * kBarThicknessPx;
}

std::string RenderBarSvg(const BarPlot& plot) {
  const BarLayout layout = BarLayoutOf(plot);
  const Frame frame{layout};
  const std::vector<std::string> colors = SeriesColors(plot.series);
  return SvgDocumentStart(layout.doc_width_px, layout.doc_height_px) + GridAndAxes(frame) +
         CategoryLabels(plot, frame) + Bars(plot, colors, frame) + ReferenceLines(plot, frame) +
         Labels(plot, frame) + Legend(plot, colors, frame) + Remark(plot, frame) + "</svg>\n";
}

}  // namespace hilrig::host
