// The position and yaw reference the scenario asks the vehicle to follow: a chain of setpoints,
// each reached along a minimum-jerk (quintic) path that starts from wherever the previous one was
// at that moment, with its velocity and acceleration, so the reference is smooth even when a new
// setpoint interrupts a transition. The DUT receives this reference; envelopes measure against it.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace hilrig::host {

struct ReferenceSample {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_m_s2 = Eigen::Vector3d::Zero();
  double yaw_rad = 0;
};

struct SetpointCommand {
  double at_s = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0;
  double transition_s = 0;
};

class ReferenceTrajectory {
 public:
  // `setpoints` may come in any order; equal times keep their given order.
  ReferenceTrajectory(const ReferenceSample& initial, std::vector<SetpointCommand> setpoints);

  ReferenceSample Evaluate(double time_s) const;

 private:
  // One quintic per axis (x, y, z, yaw) over [start_s, start_s + duration_s]; held after, at
  // `held` (its end, at rest), kept once: a scenario spends most ticks holding a setpoint.
  struct Segment {
    double start_s = 0;
    double duration_s = 0;
    Eigen::Matrix<double, 4, 6> coefficients = Eigen::Matrix<double, 4, 6>::Zero();
    ReferenceSample held;
  };
  static ReferenceSample EvaluateSegment(const Segment& segment, double time_s);
  // The quintics at tau = t - start_s in [0, duration_s]; rates only while `moving`.
  static ReferenceSample SampleAt(const Segment& segment, double tau_s, bool moving);

  ReferenceSample initial_;
  std::vector<Segment> segments_;
};

}  // namespace hilrig::host
