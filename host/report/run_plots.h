// The plots written next to a run's report.json: grasp force (true, the DUT's estimate and the
// setpoint) and the vertical load (true and estimated) in grasp scenes, and the position errors in
// every scene, each with the envelopes that watch its signals drawn as bands. The runner fills a
// PlotTrace with the few columns the plots need (not whole trace rows, so an hour-long run stays
// small); WriteRunPlots renders them with svg_plot.h.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "host/trace/trace_sample.h"
#include "proto/scenario.pb.h"
#include "rig/result.h"

namespace hilrig::host {

struct PlotTrace {
  std::vector<double> time_s;
  std::vector<double> grasp_force_n;
  std::vector<double> grasp_force_estimate_n;
  std::vector<double> grasp_force_setpoint_n;
  std::vector<double> load_n;
  std::vector<double> load_estimate_n;
  std::vector<double> altitude_error_m;
  std::vector<double> horizontal_error_m;

  void Add(const TraceSample& sample);
};

inline constexpr const char* kForcePlotFile = "force.svg";
inline constexpr const char* kLoadPlotFile = "load.svg";
inline constexpr const char* kPositionPlotFile = "position.svg";
inline constexpr std::array<const char*, 3> kRunPlotFiles = {kForcePlotFile, kLoadPlotFile,
                                                             kPositionPlotFile};

// Writes force.svg and load.svg (grasp scenes only) and position.svg into `out_dir`; returns the
// file names written.
rig::Result<std::vector<std::string>> WriteRunPlots(const PlotTrace& trace,
                                                    const std::vector<proto::Envelope>& envelopes,
                                                    bool grasp_scene, const std::string& out_dir);

}  // namespace hilrig::host
