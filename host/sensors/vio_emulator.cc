#include "host/sensors/vio_emulator.h"

#include <cmath>

namespace hilrig::host {

std::int64_t VioPeriodNs(const VioParams& params) { return std::llround(1e9 / params.rate_hz); }

std::int64_t VioLatencyNs(const VioParams& params) { return std::llround(params.latency_s * 1e9); }

void CaptureVio(const VioParams& params, VioState& state, const RigidBodyState& body,
                std::int64_t now_ns) {
  if (now_ns < state.next_capture_ns) return;

  VioPose pose;
  pose.capture_time_ns = now_ns;
  pose.delivery_time_ns = now_ns + VioLatencyNs(params);
  pose.sequence = state.next_sequence++;
  pose.position_m = body.position_m;
  pose.orientation = body.orientation;
  if (params.noise_enabled) {
    RandomStream& rng = state.rng;
    const Eigen::Vector3d position_draw = StandardGaussianVector(rng);
    const Eigen::Vector3d rotation_draw = StandardGaussianVector(rng);
    pose.position_m += params.position_noise_m * position_draw;
    const Eigen::Vector3d rotation_vector = params.attitude_noise_rad * rotation_draw;
    const double angle = rotation_vector.norm();
    if (angle > 0.0) {
      pose.orientation =
          (pose.orientation * Eigen::AngleAxisd(angle, rotation_vector / angle)).normalized();
    }
  }
  state.in_flight.push_back(pose);

  const std::int64_t period = VioPeriodNs(params);
  state.next_capture_ns += period;
  if (state.next_capture_ns <= now_ns) {
    // Skip the frames the caller's gap swallowed, staying on the original schedule grid.
    const std::int64_t missed = (now_ns - state.next_capture_ns) / period + 1;
    state.next_capture_ns += missed * period;
  }
}

std::size_t DeliverVio(VioState& state, std::int64_t now_ns, std::vector<VioPose>& out) {
  std::size_t delivered = 0;
  while (!state.in_flight.empty() && state.in_flight.front().delivery_time_ns <= now_ns) {
    out.push_back(state.in_flight.front());
    state.in_flight.pop_front();
    ++delivered;
  }
  return delivered;
}

}  // namespace hilrig::host
