// The plots written next to a run's report.json, each with the envelopes that watch its signals
// drawn as bands and the timeline's events as markers: in grasp scenes the grasp force (true, the
// DUT's estimate, the setpoint) and the vertical load (true and estimated); in scenes with the
// pads each pad's true and decoded force; in every scene the position errors, x, y and z against
// the reference, and a top view of the path. Rendered with svg_plot.h from the run's
// PlottedTrace (host/trace/trace_capture.h), which keeps them decimated.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "host/checks/envelope_spec.h"
#include "host/report/svg_plot.h"
#include "host/trace/trace_capture.h"
#include "rig/result.h"

namespace hilrig::host {

inline constexpr const char* kForcePlotFile = "force.svg";
inline constexpr const char* kPadsPlotFile = "pads.svg";
inline constexpr const char* kLoadPlotFile = "load.svg";
inline constexpr const char* kPositionPlotFile = "position.svg";
inline constexpr const char* kTrajectoryPlotFile = "trajectory.svg";
inline constexpr const char* kTopViewPlotFile = "top_view.svg";
inline constexpr std::array<const char*, 6> kRunPlotFiles = {kForcePlotFile,      kPadsPlotFile,
                                                             kLoadPlotFile,       kPositionPlotFile,
                                                             kTrajectoryPlotFile, kTopViewPlotFile};

// What a run's plots show besides its trace.
struct RunPlotScene {
  std::vector<EnvelopeSpec> envelopes;
  bool grasp = false;              // an object: force.svg and load.svg
  bool pads = false;               // the tactile pads: pads.svg
  std::vector<PlotMarker> events;  // the timeline's, on every plot against time
};

// Writes the plots the scene has into `out_dir`; returns the file names written, in page order.
// Fails only on writing a file.
rig::Result<std::vector<std::string>> WriteRunPlots(const PlottedTrace& trace,
                                                    const RunPlotScene& scene,
                                                    const std::string& out_dir);

}  // namespace hilrig::host
