#include "host/scenario/output_size.h"

#include <cmath>

#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// Measured on the shipped scenes (tactile_hover: trace.csv 1 041 907 bytes over 2 501 rows with
// the pads' columns, balloon_grasp 537 a row; can.log 428 400 over 8 925 frames).
constexpr double kTraceRowBytes = 420;
constexpr double kCanLineBytes = 48;
// run.mcap, zstd-compressed, fitted to hover (9 995 326 bytes over 40 s before the pose and the
// checks' channels, 26 555 226 over 100 s with them) and balloon_grasp (10 841 123 over 34 s,
// then 11 799 072).
constexpr double kLogPhysicsTickBytes = 80;
constexpr double kLogControlTickBytes = 150;
constexpr double kLogControlTickPadBytes = 190;
constexpr double kLogTraceRowBytes = 270;  // the vehicle, the estimates, the pose
constexpr double kLogTraceRowPadBytes = 450;
constexpr double kLogEnvelopeSampleBytes = 30;  // each envelope, each trace sample
constexpr double kLogCanFrameBytes = 20;

double TraceBytes(const ScenarioConfig& config) {
  const double tick_s = static_cast<double>(config.physics_step_ns) * 1e-9;
  const double rows = config.duration_s / (tick_s * config.trace_every_ticks);
  return rows * kTraceRowBytes;
}

double CanFrames(const ScenarioConfig& config) {
  const int nodes = config.hall_sensors.tactile_enabled ? 7 : 1;
  return config.duration_s * config.hall_sensors.node_rate_hz * nodes;
}

double CanLogBytes(const ScenarioConfig& config) { return CanFrames(config) * kCanLineBytes; }

double RunLogBytes(const ScenarioConfig& config) {
  const bool pads = config.hall_sensors.tactile_enabled;
  const double ticks = config.duration_s / (static_cast<double>(config.physics_step_ns) * 1e-9);
  const double control_ticks = ticks / config.control_every_ticks;
  const double rows = ticks / config.trace_every_ticks;
  return ticks * kLogPhysicsTickBytes +
         control_ticks * (pads ? kLogControlTickPadBytes : kLogControlTickBytes) +
         rows * ((pads ? kLogTraceRowPadBytes : kLogTraceRowBytes) +
                 kLogEnvelopeSampleBytes * static_cast<double>(config.envelopes.size())) +
         CanFrames(config) * kLogCanFrameBytes;
}

std::string Gigabytes(double bytes) {
  return rig::NumberText(std::round(bytes / 1e8) / 10) + " GB";
}

}  // namespace

double EstimatedOutputBytes(const ScenarioConfig& config, bool run_log) {
  return TraceBytes(config) + CanLogBytes(config) + (run_log ? RunLogBytes(config) : 0.0);
}

std::optional<std::string> OutputSizeWarning(const ScenarioConfig& config, bool run_log) {
  const double total = EstimatedOutputBytes(config, run_log);
  if (!(total > kOutputWarningBytes)) return std::nullopt;
  const double trace_rate_hz =
      1e9 / (static_cast<double>(config.physics_step_ns) * config.trace_every_ticks);
  return "writes about " + Gigabytes(total) + " (trace.csv " + Gigabytes(TraceBytes(config)) +
         " at " + rig::NumberText(trace_rate_hz) + " Hz over " +
         rig::NumberText(config.duration_s) + " s, can.log " + Gigabytes(CanLogBytes(config)) +
         (run_log ? ", run.mcap " + Gigabytes(RunLogBytes(config)) : std::string()) +
         "); make sure the disk has room, or lower simulation.trace_rate_hz" +
         (run_log ? " (run.mcap: --no-mcap leaves it out)" : "");
}

}  // namespace hilrig::host
