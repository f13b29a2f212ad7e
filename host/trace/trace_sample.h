// One row of a run's trace: the time and every signal an envelope can watch, plus what an engineer
// needs beside them to see why (reference, attitude, rotor thrusts). The runner fills one per trace
// tick; online checks, the CSV writer and offline grading all read this same struct.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

#include "proto/scenario.pb.h"
#include "protocol/tactile_bus.h"

namespace hilrig::host {

// The pads, one per tactile node: pad i is node i + 1.
inline constexpr std::size_t kTracePadCount = tactile_bus::kTactileNodeCount;

struct TraceSample {
  double time_s = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d reference_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d roll_pitch_yaw_deg = Eigen::Vector3d::Zero();
  double tilt_deg = 0;
  std::array<double, 4> rotor_thrust_n{};
  Eigen::Vector3d estimated_position_m = Eigen::Vector3d::Zero();
  double tactile_force_max_n = 0;        // largest decoded pad force (DUT)
  double tactile_force_error_max_n = 0;  // largest |decoded - applied| pad force
  // Per pad (PAD_FORCE_N, PAD_FORCE_ESTIMATE_N, PAD_FORCE_ERROR_N): the force magnitude the plant
  // applies, the DUT's decoded one, and the magnitude of their vector difference.
  std::array<double, kTracePadCount> pad_force_n{};
  std::array<double, kTracePadCount> pad_force_estimate_n{};
  std::array<double, kTracePadCount> pad_force_error_n{};
  // Grasp scenes (all zero without an object).
  double grasp_force_n = 0;           // true: sum of the pads' normal forces
  double grasp_force_estimate_n = 0;  // the DUT's sum |f_i . n_i|
  double grasp_force_setpoint_n = 0;  // f_d while the DUT regulates, else 0
  double grasp_settled_s = 0;         // time since the grasp command last changed
  double load_n = 0;                  // true vertical contact force on the vehicle, down > 0
  double load_estimate_n = 0;         // the DUT's, from its external force estimate
  double object_mass_kg = 0;
  double servo_angle_rad = 0;
  double servo_command_rad = 0;
  bool object_damaged = false;
  bool object_dropped = false;
  double ground_force_n = 0;  // the ground's push on the vehicle (GROUND_FORCE_N)
  bool object_held = false;   // off its stand and in the pads (OBJECT_HELD)
  double slip_speed_m_s = 0;  // |object speed along the pads| while in them (SLIP_SPEED_M_S)
};

// Reads one signal from a sample. A check that watches one signal resolves its reader once and
// calls it per sample, instead of dispatching on the signal every time.
using SignalReader = double (*)(const TraceSample& sample);

// Whether `signal` is one pad's (PAD_*), which needs the pad it watches.
bool IsPadSignal(proto::Signal signal);

// The reader of `signal` (of pad `pad` for a PAD_* signal); one that gives NaN for
// SIGNAL_UNSPECIFIED, a number no Signal has, or a PAD_* signal without a pad below
// kTracePadCount.
SignalReader SignalReaderFor(proto::Signal signal, std::optional<std::size_t> pad = std::nullopt);

// The value of `signal` (of pad `pad`) in `sample`; NaN where SignalReaderFor's reader is.
double SignalValue(const TraceSample& sample, proto::Signal signal,
                   std::optional<std::size_t> pad = std::nullopt);

// Every signal an envelope can watch is finite (a NaN anywhere is a model or DUT defect worth
// counting even where no envelope looks).
bool AllSignalsFinite(const TraceSample& sample);

}  // namespace hilrig::host
