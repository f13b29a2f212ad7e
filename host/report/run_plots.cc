#include "host/report/run_plots.h"

#include <algorithm>
#include <filesystem>
#include <initializer_list>

#include "host/report/report_files.h"
#include "host/report/svg_plot.h"

namespace hilrig::host {
namespace {

PlotSeries Series(std::string name, const DecimatedSeries& kept, bool dashed = false) {
  DecimatedSeries::Points points = kept.ToPoints();
  PlotSeries series;
  series.name = std::move(name);
  series.time_s = std::move(points.time_s);
  series.value = std::move(points.value);
  series.dashed = dashed;
  return series;
}

// Every envelope on one of `signals`, as a band.
std::vector<PlotBand> BandsFor(const std::vector<EnvelopeSpec>& envelopes,
                               std::initializer_list<proto::Signal> signals) {
  std::vector<PlotBand> bands;
  for (const EnvelopeSpec& envelope : envelopes) {
    if (std::find(signals.begin(), signals.end(), envelope.signal) == signals.end()) continue;
    PlotBand band;
    band.name = "envelope " + envelope.name;
    band.lower = envelope.lower;
    band.upper = envelope.upper;
    band.from_s = envelope.from_s;
    if (envelope.until_s) band.until_s = *envelope.until_s;
    band.expect_fail = envelope.expect == EnvelopeVerdict::kFail;
    bands.push_back(std::move(band));
  }
  return bands;
}

}  // namespace

rig::Result<std::vector<std::string>> WriteRunPlots(const PlottedTrace& trace,
                                                    const std::vector<EnvelopeSpec>& envelopes,
                                                    bool grasp_scene, const std::string& out_dir) {
  std::vector<std::pair<std::string, TimePlot>> plots;
  if (grasp_scene) {
    TimePlot force;
    force.title = "Grasp force";
    force.y_label = "force (N)";
    force.series = {Series("true (plant)", trace.grasp_force_n),
                    Series("DUT estimate", trace.grasp_force_estimate_n),
                    Series("setpoint f_d", trace.grasp_force_setpoint_n, true)};
    force.bands = BandsFor(envelopes, {proto::GRASP_FORCE_N, proto::GRASP_FORCE_ESTIMATE_N});
    plots.emplace_back(kForcePlotFile, std::move(force));

    TimePlot load;
    load.title = "Vertical load of the grasped object on the vehicle";
    load.y_label = "load (N)";
    load.series = {Series("true (plant)", trace.load_n),
                   Series("DUT estimate", trace.load_estimate_n)};
    load.bands = BandsFor(envelopes, {proto::LOAD_N});
    plots.emplace_back(kLoadPlotFile, std::move(load));
  }
  TimePlot position;
  position.title = "Position error";
  position.y_label = "error (m)";
  position.series = {Series("altitude error", trace.altitude_error_m),
                     Series("horizontal error", trace.horizontal_error_m)};
  position.bands = BandsFor(
      envelopes, {proto::ALTITUDE_ERROR_M, proto::HORIZONTAL_ERROR_M, proto::POSITION_ERROR_M});
  plots.emplace_back(kPositionPlotFile, std::move(position));

  std::vector<std::string> written;
  for (const auto& [file, plot] : plots) {
    const std::string path = (std::filesystem::path(out_dir) / file).string();
    if (auto result = WriteTextFile(path, RenderSvg(plot)); !result) return result.error();
    written.push_back(file);
  }
  return written;
}

}  // namespace hilrig::host
