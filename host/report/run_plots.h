// The plots written next to a run's report.json: grasp force (true, the DUT's estimate and the
// setpoint) and the vertical load (true and estimated) in grasp scenes, and the position errors in
// every scene, each with the envelopes that watch its signals drawn as bands, rendered with
// svg_plot.h from the run's PlottedTrace (host/trace/trace_capture.h), which keeps them decimated.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "host/checks/envelope_spec.h"
#include "host/trace/trace_capture.h"
#include "rig/result.h"

namespace hilrig::host {

inline constexpr const char* kForcePlotFile = "force.svg";
inline constexpr const char* kLoadPlotFile = "load.svg";
inline constexpr const char* kPositionPlotFile = "position.svg";
inline constexpr std::array<const char*, 3> kRunPlotFiles = {kForcePlotFile, kLoadPlotFile,
                                                             kPositionPlotFile};

// Writes force.svg and load.svg (grasp scenes only) and position.svg into `out_dir`; returns the
// file names written.
rig::Result<std::vector<std::string>> WriteRunPlots(const PlottedTrace& trace,
                                                    const std::vector<EnvelopeSpec>& envelopes,
                                                    bool grasp_scene, const std::string& out_dir);

}  // namespace hilrig::host
