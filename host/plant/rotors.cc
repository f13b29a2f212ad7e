#include "host/plant/rotors.h"

#include <cmath>

namespace hilrig::host {
namespace {

// Signs of (x, y) for each rotor in units of a = L / sqrt(2).
constexpr std::array<double, kRotorCount> kRotorXSign = {+1.0, -1.0, +1.0, -1.0};
constexpr std::array<double, kRotorCount> kRotorYSign = {-1.0, +1.0, +1.0, -1.0};

inline double HalfDiagonal(const RotorParams& params) {
  return params.arm_length_m * (1.0 / std::sqrt(2.0));
}

}  // namespace

double RotorLagBlend(const RotorParams& params, double dt_s) {
  if (params.instantaneous || params.time_constant_s <= 0.0) return 1.0;
  return -std::expm1(-dt_s / params.time_constant_s);
}

RotorState StepRotorsWithBlend(const RotorParams& params, const RotorState& state,
                               const std::array<double, kRotorCount>& commanded_thrust_n,
                               double blend) {
  RotorState next;
  for (int i = 0; i < kRotorCount; ++i) {
    // Written so that a NaN command fails the first comparison and becomes 0 (std::clamp
    // would pass it through), without the libm calls fmax/fmin cost.
    const double c = commanded_thrust_n[i];
    const double non_negative = c > 0.0 ? c : 0.0;
    const double cmd = non_negative < params.max_thrust_n ? non_negative : params.max_thrust_n;
    next.thrust_n[i] = state.thrust_n[i] + blend * (cmd - state.thrust_n[i]);
  }
  return next;
}

RotorState StepRotors(const RotorParams& params, const RotorState& state,
                      const std::array<double, kRotorCount>& commanded_thrust_n, double dt_s) {
  return StepRotorsWithBlend(params, state, commanded_thrust_n, RotorLagBlend(params, dt_s));
}

Eigen::Vector3d RotorPositionBody(const RotorParams& params, int rotor) {
  const double a = HalfDiagonal(params);
  return {kRotorXSign[rotor] * a, kRotorYSign[rotor] * a, 0.0};
}

Eigen::Vector3d RotorTorqueBody(const RotorParams& params, const RotorState& state) {
  const double a = HalfDiagonal(params);
  // r x (0, 0, T) = (r_y T, -r_x T, 0). The sums are those of the sign tables in rotor order,
  // written out: a +-1 factor is exact, so they round as the loop over the tables did.
  static_assert(kRotorXSign == std::array<double, kRotorCount>{+1.0, -1.0, +1.0, -1.0});
  static_assert(kRotorYSign == std::array<double, kRotorCount>{-1.0, +1.0, +1.0, -1.0});
  static_assert(kRotorYawSign == std::array<double, kRotorCount>{-1.0, -1.0, +1.0, +1.0});
  const std::array<double, kRotorCount>& t = state.thrust_n;
  const double roll = ((-t[0] + t[1]) + t[2]) - t[3];
  const double pitch = ((-t[0] + t[1]) - t[2]) + t[3];
  const double yaw = ((-t[0] - t[1]) + t[2]) + t[3];
  return {a * roll, a * pitch, params.torque_per_thrust_m * yaw};
}

double CollectiveThrust(const RotorState& state) {
  return state.thrust_n[0] + state.thrust_n[1] + state.thrust_n[2] + state.thrust_n[3];
}

Eigen::Matrix4d RotorAllocationMatrix(const RotorParams& params) {
  const double a = HalfDiagonal(params);
  Eigen::Matrix4d m;
  for (int i = 0; i < kRotorCount; ++i) {
    m(0, i) = 1.0;
    m(1, i) = a * kRotorYSign[i];
    m(2, i) = -a * kRotorXSign[i];
    m(3, i) = params.torque_per_thrust_m * kRotorYawSign[i];
  }
  return m;
}

}  // namespace hilrig::host
