#include "host/scenario/reference_trajectory.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hilrig::host {
namespace {

using Quintic = Eigen::Matrix<double, 1, 6>;

// Coefficients c0..c5 (in powers of tau = t - start) of the quintic that starts at (p0, v0, a0)
// and rests at p1 after `duration_s`.
Quintic FitQuintic(double p0, double v0, double a0, double p1, double duration_s) {
  Quintic c = Quintic::Zero();
  c(0) = p0;
  c(1) = v0;
  c(2) = a0 / 2;
  const double T = duration_s;
  const double T2 = T * T, T3 = T2 * T, T4 = T3 * T, T5 = T4 * T;
  const double h = p1 - p0;
  c(3) = (20 * h - (12 * v0 * T) - (3 * a0 * T2)) / (2 * T3);
  c(4) = (-30 * h + (16 * v0 * T) + (3 * a0 * T2)) / (2 * T4);
  c(5) = (12 * h - (6 * v0 * T) - (a0 * T2)) / (2 * T5);
  return c;
}

double WrapAngle(double angle_rad) {
  // Most calls are already in range; remainder() is costly enough to show in the tick profile.
  if (angle_rad >= -std::numbers::pi && angle_rad <= std::numbers::pi) return angle_rad;
  return std::remainder(angle_rad, 2 * std::numbers::pi);
}

}  // namespace

ReferenceTrajectory::ReferenceTrajectory(const ReferenceSample& initial,
                                         std::vector<SetpointCommand> setpoints)
    : initial_(initial) {
  std::stable_sort(setpoints.begin(), setpoints.end(),
                   [](const auto& a, const auto& b) { return a.at_s < b.at_s; });
  for (const SetpointCommand& setpoint : setpoints) {
    const ReferenceSample from = Evaluate(setpoint.at_s);
    Segment segment;
    segment.start_s = setpoint.at_s;
    segment.duration_s = setpoint.transition_s;
    const Eigen::Vector4d start_position(from.position_m.x(), from.position_m.y(),
                                         from.position_m.z(), from.yaw_rad);
    const Eigen::Vector4d start_velocity(from.velocity_m_s.x(), from.velocity_m_s.y(),
                                         from.velocity_m_s.z(), 0);
    const Eigen::Vector4d start_acceleration(from.acceleration_m_s2.x(), from.acceleration_m_s2.y(),
                                             from.acceleration_m_s2.z(), 0);
    // Yaw turns the short way round.
    const double target_yaw = from.yaw_rad + WrapAngle(setpoint.yaw_rad - from.yaw_rad);
    const Eigen::Vector4d target(setpoint.position_m.x(), setpoint.position_m.y(),
                                 setpoint.position_m.z(), target_yaw);
    for (int axis = 0; axis < 4; ++axis) {
      if (segment.duration_s > 0) {
        segment.coefficients.row(axis) =
            FitQuintic(start_position(axis), start_velocity(axis), start_acceleration(axis),
                       target(axis), segment.duration_s);
      } else {
        segment.coefficients(axis, 0) = target(axis);
      }
    }
    segment.held = SampleAt(segment, segment.duration_s, /*moving=*/false);
    segments_.push_back(segment);
  }
}

ReferenceSample ReferenceTrajectory::EvaluateSegment(const Segment& segment, double time_s) {
  const double since_start_s = time_s - segment.start_s;
  if (!(since_start_s < segment.duration_s)) return segment.held;
  return SampleAt(segment, std::max(since_start_s, 0.0), /*moving=*/true);
}

ReferenceSample ReferenceTrajectory::SampleAt(const Segment& segment, double tau_s, bool moving) {
  Eigen::Vector4d position = Eigen::Vector4d::Zero();
  Eigen::Vector4d velocity = Eigen::Vector4d::Zero();
  Eigen::Vector4d acceleration = Eigen::Vector4d::Zero();
  for (int power = 5; power >= 0; --power) {
    position = position * tau_s + segment.coefficients.col(power);
  }
  if (moving) {
    for (int power = 5; power >= 1; --power) {
      velocity = velocity * tau_s + power * segment.coefficients.col(power);
    }
    for (int power = 5; power >= 2; --power) {
      acceleration = acceleration * tau_s + power * (power - 1) * segment.coefficients.col(power);
    }
  }
  ReferenceSample sample;
  sample.position_m = position.head<3>();
  sample.velocity_m_s = velocity.head<3>();
  sample.acceleration_m_s2 = acceleration.head<3>();
  sample.yaw_rad = WrapAngle(position(3));
  return sample;
}

ReferenceSample ReferenceTrajectory::Evaluate(double time_s) const {
  const auto after = std::upper_bound(segments_.begin(), segments_.end(), time_s,
                                      [](double t, const Segment& s) { return t < s.start_s; });
  if (after == segments_.begin()) return initial_;
  return EvaluateSegment(*std::prev(after), time_s);
}

}  // namespace hilrig::host
