// How much a run of a scene writes, estimated before it runs: trace.csv grows by a row per trace
// sample and can.log by a line per CAN frame, so a day-long scene at a fast trace rate fills a
// disk (86 400 s at 1 kHz is about 27 GB of trace). `hilrig check` and `hilrig run` warn above
// kOutputWarningBytes; a disk that fills anyway ends the run cleanly with a named error.
#pragma once

#include <optional>
#include <string>

#include "host/scenario/scenario_config.h"

namespace hilrig::host {

// Above this a run's files are worth a warning.
inline constexpr double kOutputWarningBytes = 1e9;

// trace.csv and can.log of the whole run, in bytes: about 320 bytes a trace row and 48 a logged
// frame (one per Hall node sample), as the shipped scenes write them. O(1); cannot fail.
double EstimatedOutputBytes(const ScenarioConfig& config);

// "writes about 27 GB (trace.csv 26 GB at 1000 Hz over 86400 s, can.log 1 GB)" when the estimate
// is above kOutputWarningBytes; nothing otherwise.
std::optional<std::string> OutputSizeWarning(const ScenarioConfig& config);

}  // namespace hilrig::host
