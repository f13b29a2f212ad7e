// Renders histograms as standalone SVG 1.1 text in the style of svg_plot.h: how one envelope's
// worst value spread over a sweep's cases (host/sweep/sweep_page.h), the counts of each bin stacked
// by group (the cases that met the envelope in green, those that did not in red) and the
// envelope's limits drawn as vertical lines. A pure function of the description, like RenderSvg:
// the same description gives byte-identical text. Values that are not finite cannot be binned:
// they are left out and counted in a note on the plot, and a plot with no finite value draws its
// frame and says so, never a bar.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hilrig::host {

struct HistogramGroup {
  std::string name;   // legend label, e.g. "met"; the legend adds the count
  std::string color;  // CSS colour
  std::vector<double> values;
};

// A vertical line across the plot at `value`, e.g. an envelope's limit; left out when not finite.
struct HistogramLine {
  std::string name;  // legend label, e.g. "upper 0.65 N"
  double value = 0;
};

struct HistogramPlot {
  std::string title;
  std::string x_label;                 // with unit, e.g. "worst value (N)"
  std::vector<HistogramGroup> groups;  // stacked in this order, the first at the bottom
  std::vector<HistogramLine> lines;
  int bins = 30;                        // clamped to [1, kMaxHistogramBins]
  int width_px = 520, height_px = 250;  // clamped like TimePlot's
};

inline constexpr int kMaxHistogramBins = 1000;

struct HistogramBins {
  bool any = false;       // some value was finite
  double lo = 0, hi = 1;  // the x axis: the finite values and lines, widened to round ticks
  std::vector<std::vector<std::uint64_t>> counts;  // [group][bin], equal-width bins over lo..hi
  std::uint64_t not_finite = 0;                    // values left out, over all groups
};

// The bins of `plot`: a value v goes to bin floor((v - lo) / (hi - lo) x bins), the top edge to
// the last bin. Cannot fail.
HistogramBins BinHistogram(const HistogramPlot& plot);

// The whole document. Deterministic: the same plot gives byte-identical text.
std::string RenderHistogramSvg(const HistogramPlot& plot);

}  // namespace hilrig::host
