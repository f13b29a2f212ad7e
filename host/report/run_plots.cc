#include "host/report/run_plots.h"

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <optional>

#include "host/report/report_files.h"

namespace hilrig::host {
namespace {

// A true value drawn wide and light under its thin estimate, so that both show where they agree.
constexpr double kTrueStrokePx = 4.5;
constexpr double kTrueOpacity = 0.35;
constexpr double kEstimateStrokePx = 1.3;
constexpr const char* kAxisNames[] = {"x", "y", "z"};

PlotSeries Series(std::string name, const DecimatedSeries& kept, bool dashed = false) {
  DecimatedSeries::Points points = kept.ToPoints();
  PlotSeries series;
  series.name = std::move(name);
  series.time_s = std::move(points.time_s);
  series.value = std::move(points.value);
  series.dashed = dashed;
  return series;
}

PlotSeries TrueSeries(std::string name, const DecimatedSeries& kept, const char* color) {
  PlotSeries series = Series(std::move(name), kept);
  series.color = color;
  series.stroke_px = kTrueStrokePx;
  series.opacity = kTrueOpacity;
  return series;
}

PlotSeries EstimateSeries(std::string name, const DecimatedSeries& kept, const char* color) {
  PlotSeries series = Series(std::move(name), kept);
  series.color = color;
  series.stroke_px = kEstimateStrokePx;
  return series;
}

// Every envelope on one of `signals` (for a pad's signals, on pad `pad` when given), as a band.
std::vector<PlotBand> BandsFor(const std::vector<EnvelopeSpec>& envelopes,
                               std::initializer_list<proto::Signal> signals,
                               std::optional<std::size_t> pad = std::nullopt) {
  std::vector<PlotBand> bands;
  for (const EnvelopeSpec& envelope : envelopes) {
    if (std::find(signals.begin(), signals.end(), envelope.signal) == signals.end()) continue;
    if (pad && envelope.pad && *envelope.pad != *pad) continue;
    PlotBand band;
    band.name = "envelope " + envelope.name;
    if (envelope.pad) band.name += " (pad " + std::to_string(*envelope.pad) + ")";
    band.lower = envelope.lower;
    band.upper = envelope.upper;
    band.from_s = envelope.from_s;
    if (envelope.until_s) band.until_s = *envelope.until_s;
    band.expect_fail = envelope.expect == EnvelopeVerdict::kFail;
    bands.push_back(std::move(band));
  }
  return bands;
}

// A quantity the plant knows against the DUT's estimate of it.
TimePlot TruthAndEstimate(std::string title, std::string y_label, const DecimatedSeries& truth,
                          const DecimatedSeries& estimate, std::string estimate_name) {
  TimePlot plot;
  plot.title = std::move(title);
  plot.y_label = std::move(y_label);
  plot.series = {TrueSeries("true (plant)", truth, kSeriesPalette[0]),
                 EstimateSeries(std::move(estimate_name), estimate, kSeriesPalette[1])};
  return plot;
}

TimePlot ForcePlot(const PlottedTrace& trace, const RunPlotScene& scene) {
  TimePlot force =
      TruthAndEstimate("Grasp force: true (wide, light) and the DUT's estimate", "force (N)",
                       trace.grasp_force_n, trace.grasp_force_estimate_n, "DUT estimate");
  force.series.push_back(Series("setpoint f_d", trace.grasp_force_setpoint_n, true));
  force.series.back().color = kSeriesPalette[5];
  force.bands = BandsFor(scene.envelopes, {proto::GRASP_FORCE_N, proto::GRASP_FORCE_ESTIMATE_N});
  return force;
}

// One panel per pad, each at its own scale: the six lines on one axis hide each other.
std::vector<TimePlot> PadPlots(const PlottedTrace& trace, const RunPlotScene& scene) {
  std::vector<TimePlot> pads;
  for (std::size_t pad = 0; pad < kTracePadCount; ++pad) {
    TimePlot plot =
        TruthAndEstimate("Pad " + std::to_string(pad) + " (node " + std::to_string(pad + 1) + ")",
                         "force magnitude (N)", trace.pad_force_n[pad],
                         trace.pad_force_estimate_n[pad], "decoded by the DUT");
    plot.bands =
        BandsFor(scene.envelopes,
                 {proto::PAD_FORCE_N, proto::PAD_FORCE_ESTIMATE_N, proto::TACTILE_FORCE_N}, pad);
    plot.width_px = 450;
    plot.height_px = 250;
    plot.markers = scene.events;
    pads.push_back(std::move(plot));
  }
  return pads;
}

TimePlot LoadPlot(const PlottedTrace& trace, const RunPlotScene& scene) {
  TimePlot load = TruthAndEstimate("Vertical load of the grasped object on the vehicle", "load (N)",
                                   trace.load_n, trace.load_estimate_n, "DUT estimate");
  load.bands = BandsFor(scene.envelopes, {proto::LOAD_N});
  return load;
}

TimePlot PositionErrorPlot(const PlottedTrace& trace, const RunPlotScene& scene) {
  TimePlot position;
  position.title = "Position error";
  position.y_label = "error (m)";
  position.series = {Series("altitude error", trace.altitude_error_m),
                     Series("horizontal error", trace.horizontal_error_m)};
  position.bands = BandsFor(scene.envelopes, {proto::ALTITUDE_ERROR_M, proto::HORIZONTAL_ERROR_M,
                                              proto::POSITION_ERROR_M});
  return position;
}

// x, y and z against their references, one panel each; the altitude's envelopes on z.
std::vector<TimePlot> TrajectoryPlots(const PlottedTrace& trace, const RunPlotScene& scene) {
  std::vector<TimePlot> panels;
  for (int axis = 0; axis < 3; ++axis) {
    const std::string name = kAxisNames[axis];
    TimePlot panel;
    panel.title = name == "z" ? "Altitude z and its reference" : name + " and its reference";
    panel.y_label = name + " (m)";
    PlotSeries reference = Series("reference", trace.reference_m[axis], true);
    reference.color = kSeriesPalette[5];
    reference.stroke_px = 1;
    panel.series = {Series("vehicle", trace.position_m[axis]), std::move(reference)};
    panel.series.front().color = kSeriesPalette[0];
    if (axis == 2) panel.bands = BandsFor(scene.envelopes, {proto::ALTITUDE_M});
    panel.height_px = 240;
    panel.markers = scene.events;
    panels.push_back(std::move(panel));
  }
  return panels;
}

TimePlot TopViewPlot(const PlottedTrace& trace) {
  TimePlot top;
  top.title = "Top view: the path (solid) and its reference (dashed)";
  top.x_label = "x (m)";
  top.y_label = "y (m)";
  top.equal_scale = true;
  top.width_px = 640;
  top.height_px = 520;
  PlotSeries path, reference, start;
  path.name = "vehicle";
  path.color = kSeriesPalette[0];
  reference.name = "reference";
  reference.color = kSeriesPalette[5];
  reference.dashed = true;
  reference.stroke_px = 1;
  start.name = "start (dot)";
  start.color = kSeriesPalette[1];
  start.stroke_px = 7;
  for (const DecimatedPath::Point& point : trace.path.ToPoints()) {
    path.time_s.push_back(point.x_m);
    path.value.push_back(point.y_m);
    reference.time_s.push_back(point.reference_x_m);
    reference.value.push_back(point.reference_y_m);
  }
  if (!path.time_s.empty()) {
    start.time_s = {path.time_s.front()};
    start.value = {path.value.front()};
  }
  top.series = {std::move(path), std::move(reference), std::move(start)};
  return top;
}

}  // namespace

rig::Result<std::vector<std::string>> WriteRunPlots(const PlottedTrace& trace,
                                                    const RunPlotScene& scene,
                                                    const std::string& out_dir) {
  std::vector<std::pair<std::string, std::string>> plots;  // file, SVG
  const auto add = [&](const char* file, TimePlot plot, bool marked) {
    if (marked) plot.markers = scene.events;
    plots.emplace_back(file, RenderSvg(plot));
  };
  if (scene.grasp) add(kForcePlotFile, ForcePlot(trace, scene), true);
  if (scene.pads) plots.emplace_back(kPadsPlotFile, RenderSvgGrid(PadPlots(trace, scene), 2));
  if (scene.grasp) add(kLoadPlotFile, LoadPlot(trace, scene), true);
  add(kPositionPlotFile, PositionErrorPlot(trace, scene), true);
  plots.emplace_back(kTrajectoryPlotFile, RenderSvgGrid(TrajectoryPlots(trace, scene), 1));
  add(kTopViewPlotFile, TopViewPlot(trace), false);

  std::vector<std::string> written;
  for (const auto& [file, svg] : plots) {
    const std::string path = (std::filesystem::path(out_dir) / file).string();
    if (auto result = WriteTextFile(path, svg); !result) return result.error();
    written.push_back(file);
  }
  return written;
}

}  // namespace hilrig::host
