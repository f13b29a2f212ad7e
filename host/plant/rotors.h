// The four rotors of the X-layout quadrotor: a first-order thrust lag per motor and the wrench
// the thrusts produce in the body frame. Layout (shared with the controller, must match it):
// a = L / sqrt(2); rotor 0 at (+a, -a) front-right, 1 at (-a, +a) back-left, 2 at (+a, +a)
// front-left, 3 at (-a, -a) back-right; thrust along +z body; the yaw reaction torque of rotor i
// is kRotorYawSign[i] * torque_per_thrust_m * T_i; roll/pitch torque is r_i x (0, 0, T_i).
#ifndef HILRIG_HOST_PLANT_ROTORS_H_
#define HILRIG_HOST_PLANT_ROTORS_H_

#include <Eigen/Core>
#include <array>

namespace hilrig::host {

inline constexpr int kRotorCount = 4;
inline constexpr std::array<double, kRotorCount> kRotorYawSign = {-1.0, -1.0, +1.0, +1.0};

struct RotorParams {
  double arm_length_m = 0.1;
  double torque_per_thrust_m = 0.016;
  double max_thrust_n = 4.0;
  double time_constant_s = 0.03;
  bool instantaneous = false;  // T = clamped command, no lag
};

struct RotorState {
  std::array<double, kRotorCount> thrust_n{};
};

// Exact discretization of the first-order lag for a command held over the step:
// T += (1 - exp(-dt/tau)) (cmd - T). Commands are clamped to [0, max_thrust_n].
RotorState StepRotors(const RotorParams& params, const RotorState& state,
                      const std::array<double, kRotorCount>& commanded_thrust_n, double dt_s);

// The blend factor 1 - exp(-dt/tau) (1 when instantaneous or tau <= 0). A runner with a fixed
// dt can compute it once and call StepRotorsWithBlend to keep exp() out of the tick.
double RotorLagBlend(const RotorParams& params, double dt_s);
RotorState StepRotorsWithBlend(const RotorParams& params, const RotorState& state,
                               const std::array<double, kRotorCount>& commanded_thrust_n,
                               double blend);

// Position of rotor i (0..3) in the body frame, in the rotor plane z = 0.
Eigen::Vector3d RotorPositionBody(const RotorParams& params, int rotor);

// Roll, pitch and yaw torque of the current thrusts, body frame.
Eigen::Vector3d RotorTorqueBody(const RotorParams& params, const RotorState& state);

// Sum of the four thrusts (along +z body).
double CollectiveThrust(const RotorState& state);

// Maps the thrust vector (T0..T3) to (collective, tau_x, tau_y, tau_z): the matrix the
// controller's mixer inverts; exposed so tests and tools can check the two agree.
Eigen::Matrix4d RotorAllocationMatrix(const RotorParams& params);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_PLANT_ROTORS_H_
