// dut_emu --mavlink: a stand-in for PX4 SITL on the rig's MAVLink simulator link (docs/mavlink.md),
// running the rig's own flight controller (an InProcessDut) on what the rig sends, so the rig's
// MAVLink path can be driven without PX4.
//
// MavlinkDut is the flight stack's side of the protocol with no socket in it: decoded messages of
// both links in (ODOMETRY, CAN_FRAME, HIL_GPS and HIL_SENSOR on the TCP simulator link,
// COMMAND_LONG and SET_POSITION_TARGET_LOCAL_NED on the UDP API link), NED/FRD turned into the
// rig's ENU/FLU, one controller step per HIL_SENSOR, encoded frames for each link out.
// RunMavlinkDut puts it on POSIX sockets. The DUT's only clock is HIL_SENSOR's time_usec; the OS
// clock bounds socket waits only.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "dut_emu/dut_emu_server.h"
#include "dut_emu/link_can_bus.h"
#include "host/dut/dut_port.h"
#include "host/link/dut_config_codec.h"
#include "host/link/hil_messages.h"
#include "host/link/mavlink_hil.h"
#include "host/mavlink/mavlink_frame.h"
#include "host/mavlink/mavlink_messages.h"
#include "rig/result.h"

namespace hilrig::dut_emu {

// dut_emu's exit code when the IMU readings repeat (the others are in dut_emu_server.h).
inline constexpr int kExitSensorsStale = host::kStandInExitSensorsStale;
static_assert(kExitSensorsStale != kExitOk && kExitSensorsStale != kExitFailed &&
              kExitSensorsStale != kExitUsage && kExitSensorsStale != kExitTestHook);

// Which of the two links a frame came on or goes out on.
enum class MavlinkLink : std::uint8_t {
  kSimulator,  // TCP: ODOMETRY and HIL_SENSOR in, HIL_ACTUATOR_CONTROLS out
  kApi,        // UDP: commands and setpoints in, HEARTBEAT and COMMAND_ACK out
};

// Why MavlinkDut stops taking input; kRunning while it goes on.
enum class MavlinkDutEnd : std::uint8_t {
  kRunning,
  kSensorsStale,      // kStaleRepeats HIL_SENSORs in a row with the same accelerometer and gyro
  kTimeZero,          // a HIL_SENSOR with time_usec 0
  kTimeNotAdvancing,  // a HIL_SENSOR not later than the one before
  kTimeOutOfRange,    // a time_usec whose nanoseconds do not fit the rig's int64 time
  kTooManyPoses,      // more ODOMETRY between two HIL_SENSORs than a step holds
  kStepFailed,        // the controller refused the step
  kUndecodable,       // a frame the codec does not decode
};

// MAV_RESULT values a COMMAND_ACK carries here.
enum class MavResult : std::uint8_t { kAccepted = 0, kDenied = 2, kUnsupported = 3 };

// Who sent a message (the frame header's ids); the COMMAND_ACK goes back to them.
struct MavlinkSender {
  std::uint8_t system_id = 0;
  std::uint8_t component_id = 0;
};

// The encoded frames bound for one link, in sending order, in fixed storage.
class MavlinkFrameBatch {
 public:
  static constexpr std::size_t kMaxFrames = 2;

  // Cannot fail; does not allocate.
  void Clear() { frames_ = 0; }
  // Encodes `message` as the next frame; false when the batch is full (no caller sends more than
  // kMaxFrames per input). Does not allocate.
  bool Append(const mavlink::AnyMessage& message, std::uint8_t sequence, std::uint8_t system_id,
              std::uint8_t component_id);
  // Cannot fail; does not allocate.
  std::size_t size() const { return frames_; }
  bool empty() const { return frames_ == 0; }
  // Frame `index` (< size()) as it goes on the wire. Cannot fail; does not allocate.
  std::span<const std::uint8_t> frame(std::size_t index) const {
    return {storage_[index].data(), sizes_[index]};
  }

 private:
  std::array<std::array<std::uint8_t, mavlink::kMaxFrameBytes>, kMaxFrames> storage_{};
  std::array<std::size_t, kMaxFrames> sizes_{};
  std::size_t frames_ = 0;
};

// What one input asks MavlinkDut to send, and whether it goes on.
struct MavlinkReplies {
  MavlinkFrameBatch simulator;
  MavlinkFrameBatch api;
  MavlinkDutEnd end = MavlinkDutEnd::kRunning;
  std::string why;  // when end is not kRunning: the one-line reason, without "dut_emu: "
};

// What MavlinkDut took and left, for the line it ends on.
struct MavlinkDutCounters {
  std::uint64_t sensor_steps = 0;
  std::uint64_t poses = 0;       // ODOMETRY handed to the controller
  std::uint64_t setpoints = 0;   // SET_POSITION_TARGET_LOCAL_NED taken
  std::uint64_t can_frames = 0;  // CAN_FRAME handed to the controller's bus
  std::uint64_t gps_fixes = 0;   // HIL_GPS taken
  std::uint64_t commands = 0;    // COMMAND_LONG answered
  std::uint64_t heartbeats_received = 0;
  // Messages it does not take: ones a link does not carry in the contract, ones addressed to
  // another system, poses and setpoints in a frame other than MAV_FRAME_LOCAL_NED or not finite,
  // CAN frames no bus holds.
  std::uint64_t ignored = 0;
};

// PX4's side of the simulator and API links over a DUT port. Each Handle returns what to send on
// each link, in order (the API link's first: a step's heartbeat is in the rig's socket before the
// step's answer), valid until the next call. Once an input ends it (end not kRunning) it takes
// nothing more: every later input returns that end again.
//
// Threading: one thread at a time.
class MavlinkDut {
 public:
  // PX4 marks a sensor whose readings repeat this many times in a row stale.
  static constexpr std::uint32_t kStaleRepeats = 100;
  // ODOMETRY between two HIL_SENSORs; the rig sends at most one per step.
  static constexpr std::size_t kMaxPosesPerStep = 16;
  // The flight stack's ids on both links.
  static constexpr std::uint8_t kSystemId = 1;
  static constexpr std::uint8_t kComponentId = 1;
  // One heartbeat per second of the DUT's time.
  static constexpr std::uint64_t kHeartbeatPeriodUsec = 1'000'000;

  // The rig's controller, an InProcessDut on a CAN bus that the simulator link's CAN_FRAMEs fill,
  // normalised by the firmware's rotor and servo ranges. Cannot fail.
  MavlinkDut(const host::DutFirmware& firmware, double control_period_s);
  // Any DUT port, normalised by `range`; for tests that watch what the port is sent. CAN frames
  // are counted as ignored: the port's bus is its own. Cannot fail.
  MavlinkDut(std::unique_ptr<host::DutPort> port, const host::ActuatorScale& range);
  MavlinkDut(const MavlinkDut&) = delete;
  MavlinkDut& operator=(const MavlinkDut&) = delete;

  // The HEARTBEAT that announces the DUT on the API link before any step. Cannot fail; does not
  // allocate.
  const MavlinkReplies& Announce();
  // Decodes `frame` and handles it; a frame the codec cannot decode ends the DUT (kUndecodable).
  // Does not allocate unless it ends the DUT (the reason's text).
  const MavlinkReplies& HandleFrame(const mavlink::Frame& frame, MavlinkLink link);
  // ODOMETRY and HIL_GPS: held for the next step. CAN_FRAME: onto the controller's CAN bus,
  // which it reads at the next step. HIL_SENSOR: one step (time checks, the stale rule, the held
  // poses, fix and setpoint, the IMU reading and the magnetometer and barometer readings its
  // fields_updated marks, the controller's step) answered with one HIL_ACTUATOR_CONTROLS of the
  // same time_usec, after the controller's estimates (DEBUG_FLOAT_ARRAY) and, once a second, a
  // HEARTBEAT on the API link. COMMAND_LONG: arm/disarm (400), set mode (176) and the gripper
  // (211, the grasp) are accepted when well-formed, others unsupported, each answered with a
  // COMMAND_ACK. SET_POSITION_TARGET_LOCAL_NED: held for the next step. A
  // HIL_SENSOR can end the DUT (see MavlinkDutEnd). Does not allocate unless it ends the DUT (the
  // reason's text); the controller's step is the DUT port's.
  const MavlinkReplies& Handle(const mavlink::AnyMessage& message, MavlinkLink link,
                               MavlinkSender sender = {});

  // Cannot fail; do not allocate.
  const MavlinkDutCounters& counters() const { return counters_; }
  bool arm_commanded() const { return arm_commanded_; }
  // The controller's own counters (CAN frames taken and rejected among them).
  host::DutCounters controller_counters() const { return port_->counters(); }
  MavlinkDutEnd end() const { return replies_.end; }

 private:
  void Begin();
  const MavlinkReplies& End(MavlinkDutEnd end, std::string why);
  void HandleSensor(const mavlink::HilSensor& sensor);
  void HandleOdometry(const mavlink::Odometry& odometry);
  void HandleCommand(const mavlink::CommandLong& command, MavlinkSender sender);
  void HandleSetpoint(const mavlink::SetPositionTargetLocalNed& target);
  void HandleCanFrame(const mavlink::CanFrame& message);
  void HandleGps(const mavlink::HilGps& gps);
  MavResult HandleGripper(const mavlink::CommandLong& command);
  // Whether the stale rule fires with this reading.
  bool RepeatsStale(const mavlink::HilSensor& sensor);
  void Send(MavlinkLink link, const mavlink::AnyMessage& message);
  mavlink::Heartbeat MakeHeartbeat() const;
  mavlink::HilActuatorControls MakeControls(std::uint64_t time_usec,
                                            const host::ActuatorMessage& command) const;

  LinkCanBus* can_ = nullptr;  // owned by port_; null for a port of the caller's
  std::unique_ptr<host::DutPort> port_;
  host::ActuatorScale range_;
  MavlinkReplies replies_;
  std::array<std::uint8_t, 2> sequence_{};  // per link
  // Held until the next HIL_SENSOR, whose time is their delivery time.
  std::array<host::VioMessage, kMaxPosesPerStep> poses_{};
  std::size_t poses_held_ = 0;
  std::optional<host::SetpointMessage> setpoint_held_;
  std::optional<host::GnssMessage> fix_held_;
  host::SetpointMessage last_setpoint_;
  std::uint64_t imu_sequence_ = 0;
  std::uint64_t vio_sequence_ = 0;
  std::uint64_t setpoint_sequence_ = 0;
  std::uint64_t mag_sequence_ = 0;
  std::uint64_t baro_sequence_ = 0;
  std::uint64_t gnss_sequence_ = 0;
  std::uint64_t tick_ = 0;
  std::optional<std::uint64_t> last_time_usec_;
  std::uint64_t next_heartbeat_usec_ = kHeartbeatPeriodUsec;
  // The stale rule: the last accelerometer and gyro bits, and how many readings in a row had them.
  std::array<std::uint32_t, 6> last_reading_bits_{};
  std::uint32_t repeats_ = 0;
  // The flight mode as commanded: PX4 answers to an arm command and a set mode with its heartbeat.
  bool arm_commanded_ = false;
  std::uint8_t base_mode_flags_ = 1;  // MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, as PX4 reports
  std::uint32_t custom_mode_ = 0;
  MavlinkDutCounters counters_;
};

struct MavlinkDutOptions {
  // --mavlink-serial DEVICE[,baud=N]: both links on one serial line, as PX4 on a board (HITL);
  // empty: the simulator link over TCP and the API link over UDP, as PX4 SITL.
  std::string serial_device;
  unsigned baud = 921600;
  std::string simulator_host;  // --mavlink: where the simulator link listens (TCP)
  std::uint16_t simulator_port = 0;
  std::string api_host;  // --api: the rig's API port (UDP)
  std::uint16_t api_port = 0;
  std::string config_path;  // --config: a binary proto::DutConfig
  int connect_timeout_ms = 10'000;
};

extern const char* const kMavlinkDutUsage;

// argv of dut_emu with --mavlink: --mavlink HOST:PORT --api HOST:PORT --config FILE, or
// --mavlink-serial DEVICE[,baud=N] --config FILE, in any order; an error names what is missing or
// malformed. Allocates; not on a per-step path.
rig::Result<MavlinkDutOptions> ParseMavlinkArgs(const std::vector<std::string>& args);

// The firmware and control period in the binary proto::DutConfig at `path`; fails, naming the file
// and what is wrong with it, when it cannot be read, parsed or checked. Allocates; runs once.
rig::Result<host::DutSetup> LoadMavlinkDutSetup(const std::string& path);

// Runs the stand-in until the simulator closes its link, an input ends the DUT, a socket fails or
// `stop_requested` (may be null) is set; says why in one line on `log` and returns dut_emu's exit
// code: kExitOk for a clean close after at least one step or a stop request, kExitSensorsStale
// when the stale rule fires, kExitFailed otherwise. Allocates on start; the per-step path does
// not, beyond the controller's own step.
int RunMavlinkDut(const MavlinkDutOptions& options, const std::atomic<bool>* stop_requested,
                  std::ostream& log);

// Why a parser dropped bytes; nullopt while it dropped none.
std::optional<const char*> DropReason(const mavlink::ParserCounters& counters);

// The link a message belongs to on a line that carries both: commands and setpoints are the API
// link's, the rest the simulator link's.
MavlinkLink LinkOf(std::uint32_t message_id);

}  // namespace hilrig::dut_emu
