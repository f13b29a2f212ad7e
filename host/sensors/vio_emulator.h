// The stereo visual-inertial odometry emulator: samples the true pose at the VIO frame rate,
// corrupts it (Gaussian position noise, small-angle Gaussian rotation noise applied in the body
// frame) and holds it back for the processing latency, so the controller sees poses as old as a
// real camera pipeline delivers them. Captures happen on a fixed schedule (each next capture is
// the previous *scheduled* one plus the period, so tick granularity never accumulates into rate
// drift); a pose is stamped with the tick time it was actually taken at.
#ifndef HILRIG_HOST_SENSORS_VIO_EMULATOR_H_
#define HILRIG_HOST_SENSORS_VIO_EMULATOR_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "host/plant/rigid_body.h"
#include "host/sensors/random_stream.h"

namespace hilrig::host {

struct VioParams {
  double rate_hz = 30.0;
  double latency_s = 0.03;
  double position_noise_m = 0.003;    // per axis, 1 sigma
  double attitude_noise_rad = 0.002;  // per axis of the rotation vector, 1 sigma
  bool noise_enabled = true;
};

struct VioPose {
  std::int64_t capture_time_ns = 0;
  std::int64_t delivery_time_ns = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // R_WB
  std::uint32_t sequence = 0;
};

struct VioState {
  RandomStream rng;
  std::int64_t next_capture_ns = 0;
  std::uint32_t next_sequence = 0;
  std::deque<VioPose> in_flight;  // ordered by delivery time (constant latency)
};

// Period and latency as the emulator rounds them to whole nanoseconds.
std::int64_t VioPeriodNs(const VioParams& params);
std::int64_t VioLatencyNs(const VioParams& params);

// Captures a pose when now >= next_capture (the body state must be the one at now_ns) and
// schedules it for delivery at capture + latency. At most one capture per call: if the caller
// skipped whole periods the missed frames are dropped, not delivered in a burst.
void CaptureVio(const VioParams& params, VioState& state, const RigidBodyState& body,
                std::int64_t now_ns);

// Moves every pose due by now into `out` (appends), oldest first; returns how many.
std::size_t DeliverVio(VioState& state, std::int64_t now_ns, std::vector<VioPose>& out);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_SENSORS_VIO_EMULATOR_H_
