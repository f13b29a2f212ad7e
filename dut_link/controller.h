// What a DUT's own controller implements to be flown by the rig (docs/your-dut.md): the run's
// description in, the sensor inputs in as they arrive, one control step out per control period.
// The session (dut_link/serial_session.h) speaks the link and calls these; the controller never
// sees a byte of the protocol. Plain values in SI units, floats as the link carries them, times in
// nanoseconds of the run's clock. No Eigen, no allocation: a board's firmware and a host process
// implement it alike.
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace hilrig::dut_link {

using Vec3f = std::array<float, 3>;

// The vehicle as the run's DutConfig describes it (the FlightFirmware fields a controller of any
// design needs); a field the rig did not send is 0.
struct VehicleDescription {
  double mass_kg = 0;
  double gravity_m_s2 = 0;
  std::array<double, 3> inertia_kg_m2 = {0, 0, 0};  // principal moments, body x, y, z
  double arm_length_m = 0;                          // rotor hub to the centre of mass
  double torque_per_thrust_m = 0;                   // yaw torque a rotor's thrust makes
  double max_thrust_per_rotor_n = 0;
};

// A run starts with this. `config` is the whole DutConfig message, for a controller that reads
// more of it (dut_fw's reads every gain); it is valid during the call only.
struct RunDescription {
  double control_period_s = 0;  // positive and finite
  VehicleDescription vehicle;
  std::span<const std::uint8_t> config;
};

// Body-frame rates and specific force (FRD is not used: the rig's body frame is x forward, y left,
// z up, so at rest the accelerometer reads about +9.81 on z).
struct ImuSample {
  Vec3f gyro_rad_s = {0, 0, 0};
  Vec3f accel_m_s2 = {0, 0, 0};
  std::int64_t time_ns = 0;
};

// The VIO's pose of the body in the world (z up), stamped with when its image was taken.
struct VioSample {
  Vec3f position_m = {0, 0, 0};
  std::array<float, 4> orientation_wxyz = {1, 0, 0, 0};
  std::int64_t capture_time_ns = 0;
};

// The scenario's reference; the session keeps the fields the rig did not change since the last one.
struct Setpoint {
  Vec3f position_m = {0, 0, 0};
  Vec3f velocity_m_s = {0, 0, 0};
  Vec3f acceleration_m_s2 = {0, 0, 0};
  float yaw_rad = 0;
  bool grasp_regulate = false;  // false: hold the gripper open
  float grasp_force_n = 0;
  float grasp_reference_angle_rad = 0;
};

// A frame from the tactile CAN bus (proto/TACTILE_PROTOCOL.md), stamped with the step it arrived
// for.
struct CanFrameIn {
  std::uint16_t id = 0;
  std::uint8_t len = 0;
  std::array<std::uint8_t, 8> data{};
  std::int64_t time_ns = 0;
};

// What one control step commands. The estimates are optional: the rig plots and checks them
// when given and leaves them out of the verdict when not.
struct StepOutput {
  std::array<float, 4> rotor_thrust_n = {0, 0, 0, 0};  // rotor order: docs/your-dut.md
  bool armed = false;
  float servo_angle_rad = 0;
  Vec3f estimated_position_m = {0, 0, 0};
  bool tactile_ready = false;  // the force estimates below are valid
  float grasp_force_estimate_n = 0;
  Vec3f external_force_world_n = {0, 0, 0};
  std::array<Vec3f, 6> pad_force_sensor_n = {};  // each pad's force, in its sensor frame
};

class Controller {
 public:
  // A new run. Returns null to fly it, or why not (the session says so to the rig and the run
  // fails with it); called again for every run, so it starts over.
  virtual const char* Configure(const RunDescription& run) = 0;
  virtual void OnImu(const ImuSample& imu) = 0;
  virtual void OnVio(const VioSample& vio) = 0;
  virtual void OnSetpoint(const Setpoint& setpoint) = 0;
  virtual void OnCanFrame(const CanFrameIn& frame) = 0;
  // One control step at `now_ns`, one control period after the previous one.
  virtual StepOutput Step(std::int64_t now_ns) = 0;

 protected:
  ~Controller() = default;
};

}  // namespace hilrig::dut_link
