// The HIL link messages as plain structs: the same fields as proto/hil_link.proto, without the
// cost of protobuf objects in the lockstep loop. A DUT in this process takes them directly; a DUT
// in another process gets them encoded as hil_link.proto messages by a link transport.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <variant>

#include "proto/hil_link_tags.h"

namespace hilrig::host {

// proto/hil_link.proto's LinkProtocol, through the generated header of its numbers.
inline constexpr std::uint32_t kHilLinkProtocolVersion =
    proto_tags::LinkProtocol::kLinkProtocolVersion;

struct LinkStamp {
  std::uint64_t sequence = 0;  // per stream, from 0, without gaps
  std::int64_t time_ns = 0;    // simulated time the message was sent
};

// Each message the runner sends to the DUT names its stream (kStream): the name of its
// response latency in real-time reports, and of its payload in proto/hil_link.proto.
struct ImuMessage {
  static constexpr const char* kStream = "imu";
  LinkStamp stamp;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
  // An axis read its full scale: the reading is the range, not the motion.
  bool gyro_clipped = false;
  bool accel_clipped = false;
};

struct VioMessage {
  static constexpr const char* kStream = "vio";
  LinkStamp stamp;  // stamp.time_ns is the delivery time
  std::int64_t capture_time_ns = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

struct SetpointMessage {
  static constexpr const char* kStream = "setpoint";
  LinkStamp stamp;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_m_s2 = Eigen::Vector3d::Zero();
  double yaw_rad = 0;
  // The grasp command rides with the setpoint: open the frame (false), or regulate the grasp force
  // at grasp_force_n starting from the servo angle where contact is expected.
  bool grasp_regulate = false;
  double grasp_force_n = 0;
  double grasp_reference_angle_rad = 0;
};

struct ActuatorMessage {
  LinkStamp stamp;
  std::uint64_t answers_sequence = 0;  // the control tick this command answers
  std::array<double, 4> rotor_thrust_n{};
  bool armed = false;
  // DUT telemetry for the trace: its state estimate and its decoded pad forces (sensor frames,
  // zero until its start-up zeroing is done).
  Eigen::Vector3d estimated_position_m = Eigen::Vector3d::Zero();
  std::array<Eigen::Vector3d, 6> tactile_force_sensor_n = {
      Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
      Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  bool tactile_ready = false;
  double servo_angle_rad = 0;  // the gripper servo command
  // Telemetry of the force-aware loops: the grasp force estimate sum |f_i . n_i| and the external
  // force R_WB sum R_BSi f_i, as the DUT computed them this step (zero until its pads are zeroed).
  double grasp_force_estimate_n = 0;
  Eigen::Vector3d external_force_world_n = Eigen::Vector3d::Zero();
};

// The navigation sensors a flight stack fuses besides the IMU and VIO (PX4's EKF2: magnetometer,
// barometer, GNSS). The rig's own controller takes its heading and position from the VIO and
// takes none of them; the runner emulates them only for a DUT that says it takes them
// (DutPort::TakesNavigationSensors).
struct MagnetometerMessage {
  static constexpr const char* kStream = "mag";
  LinkStamp stamp;
  Eigen::Vector3d field_body_t = Eigen::Vector3d::Zero();  // FLU body frame, tesla
};

struct BarometerMessage {
  static constexpr const char* kStream = "baro";
  LinkStamp stamp;
  double pressure_pa = 0;
  double temperature_c = 0;
};

struct GnssMessage {
  static constexpr const char* kStream = "gnss";
  LinkStamp stamp;
  double latitude_deg = 0;
  double longitude_deg = 0;
  double altitude_m = 0;                                   // above mean sea level
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();  // the rig's world: east, north, up
  double horizontal_accuracy_m = 0;                        // one standard deviation
  double vertical_accuracy_m = 0;
  std::uint8_t satellites = 0;
};

// Everything the runner sends to the DUT, one alternative per stream. A new DUT-facing stream is
// one more alternative here; the in-process DUT and the link codec then say how they take it.
using DutInput = std::variant<ImuMessage, VioMessage, SetpointMessage, MagnetometerMessage,
                              BarometerMessage, GnssMessage>;
inline constexpr std::size_t kDutInputStreams = std::variant_size_v<DutInput>;

// Calls `take` with the message `input` holds. Like std::visit, but a chain of index compares the
// compiler inlines: the runner sends two messages every tick, and std::visit's dispatch table is
// an indirect call each time.
template <typename Take>
void VisitDutInput(const DutInput& input, Take&& take) {
  [&]<std::size_t... kIndex>(std::index_sequence<kIndex...>) {
    (void)((input.index() == kIndex ? (take(*std::get_if<kIndex>(&input)), true) : false) || ...);
  }
  (std::make_index_sequence<kDutInputStreams>());
}

inline const LinkStamp& StampOf(const DutInput& input) {
  const LinkStamp* stamp = nullptr;
  VisitDutInput(input, [&stamp](const auto& message) { stamp = &message.stamp; });
  return *stamp;
}

// The kStream of alternative `index` of DutInput ("imu", "vio", ...).
inline const char* DutInputStream(std::size_t index) {
  const char* name = nullptr;
  [&]<std::size_t... kIndex>(std::index_sequence<kIndex...>) {
    (void)((index == kIndex ? (name = std::variant_alternative_t<kIndex, DutInput>::kStream, true)
                            : false) ||
           ...);
  }
  (std::make_index_sequence<kDutInputStreams>());
  return name;
}

}  // namespace hilrig::host
