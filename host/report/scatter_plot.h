// Renders log-log scatter plots as standalone SVG 1.1 text, in the style of svg_plot.h: the work-
// precision plot of `hilrig bench` (error against wall time per simulated second, one colour per
// run family, the Pareto front as a line, a label by each point). A pure function of the plot
// description, like RenderSvg: the same description gives byte-identical text. Points that a log
// axis cannot show (zero, negative, NaN, Inf) are left out and counted in a note on the plot, so
// a run with no error (the reference) or a broken run never breaks the picture. The axis choice is
// public so that tests can compute expected pixels independently.
#pragma once

#include <string>
#include <vector>

#include "host/report/svg_plot.h"

namespace hilrig::host {

struct ScatterPoint {
  double x = 0, y = 0;
  std::string label;  // drawn next to the marker; empty: none
};

struct ScatterSeries {
  std::string name;   // legend label, e.g. "RK4"
  std::string color;  // CSS colour; empty = the next colour of kSeriesPalette
  std::vector<ScatterPoint> points;
};

struct ScatterPlot {
  std::string title;
  std::string x_label, y_label;  // with units
  std::vector<ScatterSeries> series;
  std::vector<ScatterPoint> front;  // drawn as a line through the points in order; labels unused
  std::string front_name = "Pareto front";
  int width_px = 640, height_px = 440;  // clamped like TimePlot's
};

// A decade axis: the range is whole powers of ten around the data, ticks on powers of ten (every
// `decade_step`-th one when there are more than 8 decades).
struct LogAxis {
  int lo_exponent = 0, hi_exponent = 1;  // the axis spans 10^lo .. 10^hi, lo < hi
  int decade_step = 1;
  std::vector<int> tick_exponents;
  std::vector<std::string> labels;  // "1e-3", "0.01", "1", "100", "1e+04"
};

// The axis around [min_value, max_value]; anything but 0 < min <= max (finite) gives the axis
// 10^0 .. 10^1.
LogAxis LogTicks(double min_value, double max_value);

// Pixel position of `value` on `axis` drawn from `start_px` over `length_px` (increasing with the
// value); values outside the axis are clamped to its ends.
double LogAxisPx(const LogAxis& axis, double value, double start_px, double length_px);

// The whole document for one plot.
std::string RenderScatterSvg(const ScatterPlot& plot);

// Several plots in one document, `columns` per row (at least 1), each in its own nested <svg>.
std::string RenderScatterGrid(const std::vector<ScatterPlot>& plots, int columns);

}  // namespace hilrig::host
