// How much a run of a scene writes, estimated before it runs: trace.csv grows by a row per trace
// sample, can.log by a line per CAN frame and run.mcap by every exchange with the DUT, so a
// day-long scene fills a disk (86 400 s at a 1 kHz trace is about 36 GB of trace and 43 GB of log).
// `hilrig check` and `hilrig run` warn above kOutputWarningBytes; a disk that fills anyway ends the
// run cleanly with a named error.
#pragma once

#include <optional>
#include <string>

#include "host/scenario/scenario_config.h"

namespace hilrig::host {

// Above this a run's files are worth a warning.
inline constexpr double kOutputWarningBytes = 1e9;

// trace.csv, can.log and (with `run_log`) run.mcap of the whole run, in bytes: about 420 bytes a
// trace row and 48 a logged frame (one per Hall node sample); run.mcap, compressed, about 80 bytes
// a physics tick (the IMU), 150 a control tick (setpoint, step, command; 190 with the pads), 270
// a trace sample (450 with the pads) and 30 more per envelope, and 20 a CAN frame, as the shipped
// scenes write them. O(1); cannot fail.
double EstimatedOutputBytes(const ScenarioConfig& config, bool run_log = true);

// "writes about 80 GB (trace.csv 36 GB at 1000 Hz over 86400 s, can.log 0.2 GB, run.mcap 43 GB)"
// when the estimate is above kOutputWarningBytes; nothing otherwise.
std::optional<std::string> OutputSizeWarning(const ScenarioConfig& config, bool run_log = true);

}  // namespace hilrig::host
