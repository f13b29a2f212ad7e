// A team's own flight controller, written against the DUT-side link library alone
// (dut_link/controller.h) and nothing of the rig's dut_fw: what docs/your-dut.md walks through.
// It flies position setpoints with a cascade of the textbook kind and leaves the gripper open.
//
// Estimate: the attitude q is the last VIO orientation; position p and velocity v run a
// complementary filter at the IMU's rate,
//   v += (R(q) a_imu - g e_z) dt,   p += v dt,
// pulled towards each VIO position p_vio by  p += k_p e dt_vio,  v += k_v e dt_vio,  e = p_vio - p.
// Position loop:  a_cmd = K_p (p_ref - p) + K_d (v_ref - v) + a_ref,   f = m (a_cmd + g e_z),
// the desired body z axis along f (tilt limited), yaw held at the reference's.
// Attitude loop (on SO(3)):  e_R = ½ vee(R_dᵀR − RᵀR_d),  τ = −J (ω_n² e_R + 2ζω_n ω),
// collective T = f · (R e_z). The rotors take (T, τ) through the rig's X layout (docs/your-dut.md):
//   T_i = T/4 + (y_i τx − x_i τy)/(4a²) + s_i τz/(4κ),  clamped to [0, T_max].
// Armed from the first VIO pose on. No allocation, no exceptions; Step is O(1).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include "dut_link/controller.h"

namespace hilrig::examples {

// 3-vectors and 3x3 matrices (row-major) in float, as small as this controller needs.
using V3 = std::array<float, 3>;
using M3 = std::array<V3, 3>;

inline V3 Add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline V3 Sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline V3 Scale(const V3& a, float k) { return {k * a[0], k * a[1], k * a[2]}; }
inline float Dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline V3 Cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline float Norm(const V3& a) { return std::sqrt(Dot(a, a)); }
inline V3 Column(const M3& m, int c) { return {m[0][c], m[1][c], m[2][c]}; }
inline V3 Times(const M3& m, const V3& v) { return {Dot(m[0], v), Dot(m[1], v), Dot(m[2], v)}; }

// R(q) for a unit quaternion (w, x, y, z): body to world.
inline M3 RotationOf(const std::array<float, 4>& q) {
  const float w = q[0], x = q[1], y = q[2], z = q[3];
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

struct HoverGains {
  float position_kp_per_s2 = 6.0f;
  float position_kd_per_s = 4.0f;
  float attitude_natural_rad_s = 25.0f;
  float attitude_damping = 0.8f;
  float max_tilt_rad = 0.5f;
  float filter_position_per_s = 6.0f;    // k_p
  float filter_velocity_per_s2 = 12.0f;  // k_v
};

class HoverController final : public dut_link::Controller {
 public:
  explicit HoverController(const HoverGains& gains = {}) : gains_(gains) {}

  const char* Configure(const dut_link::RunDescription& run) override {
    const dut_link::VehicleDescription& v = run.vehicle;
    if (!(v.mass_kg > 0) || !(v.gravity_m_s2 > 0) || !(v.arm_length_m > 0) ||
        !(v.torque_per_thrust_m > 0) || !(v.max_thrust_per_rotor_n > 0)) {
      return "hover_dut needs the vehicle's mass, gravity, arm, torque per thrust and max thrust";
    }
    for (const double moment : v.inertia_kg_m2) {
      if (!(moment > 0)) return "hover_dut needs the vehicle's inertia";
    }
    vehicle_ = v;
    state_ = State{};
    return nullptr;
  }

  void OnImu(const dut_link::ImuSample& imu) override {
    state_.gyro_rad_s = imu.gyro_rad_s;
    if (!state_.vio_seen) return;
    if (state_.last_imu_ns) {
      const float dt_s = float(imu.time_ns - *state_.last_imu_ns) * 1e-9f;
      V3 accel_world = Times(RotationOf(state_.orientation_wxyz), imu.accel_m_s2);
      accel_world[2] -= float(vehicle_.gravity_m_s2);
      state_.velocity_m_s = Add(state_.velocity_m_s, Scale(accel_world, dt_s));
      state_.position_m = Add(state_.position_m, Scale(state_.velocity_m_s, dt_s));
    }
    state_.last_imu_ns = imu.time_ns;
  }

  void OnVio(const dut_link::VioSample& vio) override {
    state_.orientation_wxyz = vio.orientation_wxyz;
    if (!state_.vio_seen) {
      state_.position_m = vio.position_m;
      state_.vio_seen = true;
    } else {
      const float dt_s =
          std::clamp(float(vio.capture_time_ns - state_.last_vio_ns) * 1e-9f, 0.0f, 0.1f);
      const V3 error = Sub(vio.position_m, state_.position_m);
      state_.position_m =
          Add(state_.position_m, Scale(error, std::min(1.0f, gains_.filter_position_per_s * dt_s)));
      state_.velocity_m_s =
          Add(state_.velocity_m_s, Scale(error, gains_.filter_velocity_per_s2 * dt_s));
    }
    state_.last_vio_ns = vio.capture_time_ns;
  }

  void OnSetpoint(const dut_link::Setpoint& setpoint) override { setpoint_ = setpoint; }

  // The gripper stays open: this controller reads no tactile frame.
  void OnCanFrame(const dut_link::CanFrameIn&) override {}

  dut_link::StepOutput Step(std::int64_t) override {
    dut_link::StepOutput out;
    out.estimated_position_m = state_.position_m;
    if (!state_.vio_seen) return out;
    const M3 rotation = RotationOf(state_.orientation_wxyz);
    const V3 force_n = ThrustVector();
    const V3 torque_nm = AttitudeTorque(rotation, DesiredRotation(force_n));
    const float collective_n = std::max(0.0f, Dot(force_n, Column(rotation, 2)));
    out.rotor_thrust_n = Mix(collective_n, torque_nm);
    out.armed = true;
    return out;
  }

 private:
  struct State {
    V3 position_m = {0, 0, 0};
    V3 velocity_m_s = {0, 0, 0};
    std::array<float, 4> orientation_wxyz = {1, 0, 0, 0};
    V3 gyro_rad_s = {0, 0, 0};
    bool vio_seen = false;
    std::int64_t last_vio_ns = 0;
    std::optional<std::int64_t> last_imu_ns;
  };

  // f = m (a_cmd + g e_z), tilted at most max_tilt_rad from vertical.
  V3 ThrustVector() const {
    const V3 position_error = Sub(setpoint_.position_m, state_.position_m);
    const V3 velocity_error = Sub(setpoint_.velocity_m_s, state_.velocity_m_s);
    V3 accel = Add(Add(Scale(position_error, gains_.position_kp_per_s2),
                       Scale(velocity_error, gains_.position_kd_per_s)),
                   setpoint_.acceleration_m_s2);
    accel[2] = std::max(accel[2] + float(vehicle_.gravity_m_s2), 0.1f);
    const float horizontal = std::hypot(accel[0], accel[1]);
    const float max_horizontal = accel[2] * std::tan(gains_.max_tilt_rad);
    if (horizontal > max_horizontal) {
      accel[0] *= max_horizontal / horizontal;
      accel[1] *= max_horizontal / horizontal;
    }
    return Scale(accel, float(vehicle_.mass_kg));
  }

  // Body z along f, body x towards the reference's yaw.
  M3 DesiredRotation(const V3& force_n) const {
    const V3 z_axis = Scale(force_n, 1.0f / Norm(force_n));
    const V3 heading = {std::cos(setpoint_.yaw_rad), std::sin(setpoint_.yaw_rad), 0.0f};
    V3 y_axis = Cross(z_axis, heading);
    y_axis = Scale(y_axis, 1.0f / Norm(y_axis));
    const V3 x_axis = Cross(y_axis, z_axis);
    return {{{x_axis[0], y_axis[0], z_axis[0]},
             {x_axis[1], y_axis[1], z_axis[1]},
             {x_axis[2], y_axis[2], z_axis[2]}}};
  }

  V3 AttitudeTorque(const M3& r, const M3& desired) const {
    // E = R_dᵀR − RᵀR_d is skew; e_R is half its vee.
    M3 e{};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        e[i][j] = Dot(Column(desired, i), Column(r, j)) - Dot(Column(r, i), Column(desired, j));
    }
    const V3 attitude_error = {0.5f * e[2][1], 0.5f * e[0][2], 0.5f * e[1][0]};
    const float wn = gains_.attitude_natural_rad_s;
    V3 torque{};
    for (int axis = 0; axis < 3; ++axis) {
      torque[axis] = -float(vehicle_.inertia_kg_m2[axis]) *
                     (wn * wn * attitude_error[axis] +
                      2 * gains_.attitude_damping * wn * state_.gyro_rad_s[axis]);
    }
    return torque;
  }

  // The rig's X layout: rotor i at (x_i, y_i) = a (sx_i, sy_i), a = L/√2, yaw sign s_i.
  std::array<float, 4> Mix(float collective_n, const V3& torque_nm) const {
    static constexpr std::array<float, 4> kX = {+1, -1, +1, -1};
    static constexpr std::array<float, 4> kY = {-1, +1, +1, -1};
    static constexpr std::array<float, 4> kYawSign = {-1, -1, +1, +1};
    const float a = float(vehicle_.arm_length_m) / std::sqrt(2.0f);
    const float kappa = float(vehicle_.torque_per_thrust_m);
    const float max_n = float(vehicle_.max_thrust_per_rotor_n);
    std::array<float, 4> thrust{};
    for (std::size_t i = 0; i < thrust.size(); ++i) {
      const float t = collective_n / 4 +
                      (kY[i] * a * torque_nm[0] - kX[i] * a * torque_nm[1]) / (4 * a * a) +
                      kYawSign[i] * torque_nm[2] / (4 * kappa);
      thrust[i] = std::clamp(t, 0.0f, max_n);
    }
    return thrust;
  }

  HoverGains gains_;
  dut_link::VehicleDescription vehicle_;
  dut_link::Setpoint setpoint_;
  State state_;
};

}  // namespace hilrig::examples
