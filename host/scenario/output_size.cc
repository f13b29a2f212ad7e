#include "host/scenario/output_size.h"

#include <cmath>

#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// Measured on the shipped scenes (tactile_hover: trace.csv 1 041 907 bytes over 2 501 rows with
// the pads' columns, balloon_grasp 537 a row; can.log 428 400 over 8 925 frames).
constexpr double kTraceRowBytes = 420;
constexpr double kCanLineBytes = 48;

double TraceBytes(const ScenarioConfig& config) {
  const double tick_s = static_cast<double>(config.physics_step_ns) * 1e-9;
  const double rows = config.duration_s / (tick_s * config.trace_every_ticks);
  return rows * kTraceRowBytes;
}

double CanLogBytes(const ScenarioConfig& config) {
  const int nodes = config.hall_sensors.tactile_enabled ? 7 : 1;
  return config.duration_s * config.hall_sensors.node_rate_hz * nodes * kCanLineBytes;
}

std::string Gigabytes(double bytes) {
  return rig::NumberText(std::round(bytes / 1e8) / 10) + " GB";
}

}  // namespace

double EstimatedOutputBytes(const ScenarioConfig& config) {
  return TraceBytes(config) + CanLogBytes(config);
}

std::optional<std::string> OutputSizeWarning(const ScenarioConfig& config) {
  const double total = EstimatedOutputBytes(config);
  if (!(total > kOutputWarningBytes)) return std::nullopt;
  const double trace_rate_hz =
      1e9 / (static_cast<double>(config.physics_step_ns) * config.trace_every_ticks);
  return "writes about " + Gigabytes(total) + " (trace.csv " + Gigabytes(TraceBytes(config)) +
         " at " + rig::NumberText(trace_rate_hz) + " Hz over " +
         rig::NumberText(config.duration_s) + " s, can.log " + Gigabytes(CanLogBytes(config)) +
         "); make sure the disk has room, or lower simulation.trace_rate_hz";
}

}  // namespace hilrig::host
