// The MAVLink link's half of a MAVLink DUT (host/linked_dut/mavlink_dut.h): a flight stack driven
// as PX4's simulator drives it (docs/mavlink.md). The rig listens on TCP for the simulator link
// and binds a UDP port for the offboard API link; Open starts `dut_emu --mavlink` (PX4's stand-in
// running the rig's controller) and waits for it to connect and to send its API heartbeat. A
// request sends a sensor step on the control ticks that fall on the sensor period (250 Hz): the
// setpoint and commands (the grasp as MAV_CMD_DO_GRIPPER) on the API link, the VIO poses as
// ODOMETRY, a new GNSS fix as HIL_GPS, and one HIL_SENSOR (with the magnetometer and barometer
// readings that are new since the step before); the DUT's HIL_ACTUATOR_CONTROLS of the same time
// answers it, and its estimates for the trace come as DEBUG_FLOAT_ARRAY on the API link. The ticks
// between sensor steps are answered at once with the last command, as the vehicle's motors hold it.
// Every tick's tactile CAN frames go on the simulator link as CAN_FRAME, as they reach the runner's
// DUT end. Every frame both ways goes into the run folder's mavlink.tlog, stamped with the run's
// time.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "host/link/byte_stream.h"
#include "host/link/child_process.h"
#include "host/link/dut_firmware.h"
#include "host/link/mavlink_hil.h"
#include "host/link/udp_socket.h"
#include "host/linked_dut/dut_link.h"
#include "host/mavlink/mavlink_frame.h"
#include "host/mavlink/mavlink_messages.h"
#include "host/mavlink/tlog.h"

namespace hilrig::host {

struct MavlinkDutOptions {
  // true: start PX4's stand-in, dut_emu --mavlink, on ports of the rig's choosing; false: wait for
  // a flight stack the user starts (PX4 SITL) on sim_port and api_port.
  bool start_stand_in = true;
  std::uint16_t sim_port = 0;  // the TCP simulator link; 0: a free one (PX4: 4560)
  std::uint16_t api_port = 0;  // the UDP API link; 0: a free one (PX4's offboard port: 14540)
  // PX4's boot answers its first sensor steps late (14 to 19 steps): until its first
  // HIL_ACTUATOR_CONTROLS arrives, a step waits first_answer_wait_s of wall time for its answer
  // and is then answered with the last command, and the late answers to those steps are taken for
  // the vehicle's outputs, not for answers. The wait keeps the rig from racing ahead of a flight
  // stack that is still booting.
  bool first_answers_late = false;
  double first_answer_wait_s = 0.05;
  std::ostream* notes = nullptr;  // where the wait for a flight stack is announced (may be null)
  std::string dut_emu_path;       // empty: "dut_emu" next to the running executable
  std::vector<std::string> extra_args;  // after dut_emu's arguments (test hooks)
  std::string address = "127.0.0.1";
  double start_timeout_s = 10.0;  // to connect and send the API heartbeat
  // How long, in the run's time, the DUT may refuse or leave unanswered the arm and offboard
  // commands, which go again once a second until accepted (PX4 refuses to arm for its first
  // seconds, until its estimator has settled).
  double command_timeout_s = 10.0;
  // PX4 integrates its IMU at 250 Hz; a sensor step goes every round(period / control period)
  // control ticks (at least every tick).
  double sensor_period_s = 0.004;
  // Where the run's mavlink.tlog goes (LinkedDut passes the run folder); empty: no log.
  std::string tlog_path;
  const std::atomic<bool>* stop_requested = nullptr;  // ends the wait for the DUT early

  // HITL: a flight stack on a board, over one serial line that carries both links, in real time.
  // The board keeps its own clock: it streams HIL_ACTUATOR_CONTROLS at its own rate and stamps
  // them with its time, so each control tick is answered at once with the latest outputs, and
  // the run stops when none came for controls_timeout_s (first_controls_timeout_s from the
  // first sensor step, for a board that has just seen its first one). With start_stand_in the rig
  // opens a pseudo-terminal pair and starts PX4's stand-in on its other end (dut_emu
  // --mavlink-serial); otherwise serial_device is the board's port, opened at `baud`.
  bool hitl = false;
  std::string serial_device;
  unsigned baud = kHitlDefaultBaud;
  double controls_timeout_s = 0.5;
  double first_controls_timeout_s = 5.0;

  // PX4's HITL default; at least kHitlMinimumBaud: the sensor steps, poses and setpoints alone
  // are about 40 kB/s.
  static constexpr unsigned kHitlDefaultBaud = 921600;
  static constexpr unsigned kHitlMinimumBaud = 460800;
};

// Checks the options: an IPv4 address, positive finite periods and timeouts.
rig::Result<void> ValidateMavlinkDutOptions(const MavlinkDutOptions& options);

class MavlinkDutLink final : public DutLink {
 public:
  MavlinkDutLink(const DutFirmware& firmware, double control_period_s,
                 const MavlinkDutOptions& options);
  ~MavlinkDutLink() override;

  rig::Result<void> Open(const rig::Clock& clock) override;
  void SetRunFolder(const std::string& folder) override;
  rig::Result<void> Input(const DutInput& input, bool realtime, std::int64_t sent_wall_ns) override;
  rig::Result<void> Request(const LinkRequest& request) override;
  DutLinkEvent Receive(int timeout_ms) override;
  rig::Result<ActuatorMessage> TakeAnswer(std::int64_t arrival_wall_ns) override;
  bool has_peer() const override { return child_.has_value(); }
  std::optional<std::string> PeerExit() override;
  void Close(bool goodbye) override;
  std::string description() const override;
  // What the DUT sent instead of an answer, when it sent bytes that were no frame.
  std::string timeout_detail() const override;
  std::string metric_prefix() const override { return "mavlink_"; }
  std::vector<rig::Metric> metrics(bool realtime) const override;

 private:
  // Frames `message` onto `stream` (the simulator link) or the API link (null), and into the log.
  rig::Result<void> SendSim(const mavlink::AnyMessage& message);
  rig::Result<void> SendApi(const mavlink::AnyMessage& message);
  void Log(std::span<const std::uint8_t> frame);
  void LogReceived(const mavlink::Frame& frame);
  // What the API link brought since the last look: the commands' acknowledgements.
  rig::Result<void> DrainApi();
  // Each frame the runner's DUT endpoint received, as CAN_FRAME on the simulator link.
  rig::Result<void> ForwardCanFrames(const std::vector<rig::TimedCanFrame>& frames);
  // Sends each command not accepted yet, at most once a second.
  rig::Result<void> SendCommandsDue();
  // A command refused or unanswered for longer than command_timeout_s.
  std::optional<rig::Error> CommandOverdue() const;
  // The next frame of the simulator link, waiting at most timeout_ms; a closed or failed link is
  // an error.
  rig::Result<std::optional<mavlink::Frame>> NextSimFrame(int timeout_ms);
  // The stand-in's or flight stack's heartbeat on the API link.
  rig::Result<void> AwaitPeer(const rig::Clock& clock, std::int64_t deadline_ns);
  // Waits for a heartbeat that `probe` (a WaitForPeer attempt) looks for; `where` says where it
  // was awaited ("to the API port 14540") in the timeout's error.
  using HeartbeatProbe = std::function<std::optional<rig::Result<void>>(int slice_ms)>;
  rig::Result<void> AwaitHeartbeat(const rig::Clock& clock, std::int64_t deadline_ns,
                                   const std::string& where, const HeartbeatProbe& probe);
  // Starts the stand-in with these link arguments (after dut_emu's own).
  rig::Result<void> StartStandIn(std::vector<std::string> link_arguments);
  // The simulator link over TCP and the API link over UDP (SITL, the stand-in in lockstep).
  rig::Result<void> OpenSockets(const rig::Clock& clock, std::int64_t deadline_ns);
  // Both links on one serial line, and the board's first heartbeat on it (HITL).
  rig::Result<void> OpenSerialLine(const rig::Clock& clock, std::int64_t deadline_ns);
  // HITL: takes what the line brought without waiting, then answers the awaited tick with the
  // latest outputs, or fails when they have gone stale.
  DutLinkEvent ReceiveHitl();
  // A frame of the API link's kind (an acknowledgement, the DUT's estimates), wherever it came.
  void TakeApiMessage(const mavlink::AnyMessage& message);
  // The answer a HIL_ACTUATOR_CONTROLS is: the awaited step's, a late one, or a fault.
  DutLinkEvent Answer(const mavlink::HilActuatorControls& controls);
  rig::Result<std::string> WriteConfigFile() const;

  DutFirmware firmware_;
  double control_period_s_;
  MavlinkDutOptions options_;
  ActuatorScale scale_;
  std::uint64_t sensor_every_ticks_ = 1;

  bool opened_ = false;
  std::optional<ChildProcess> child_;
  std::unique_ptr<ByteStream> sim_;   // closed by Close
  std::unique_ptr<UdpSocket> api_;    // null in HITL: the API frames share the serial line
  std::shared_ptr<void> slave_hold_;  // HITL with the stand-in: the pseudo-terminal's far end
  std::string line_name_;             // HITL: the serial line, for the description
  std::optional<std::int64_t> last_controls_wall_ns_;  // HITL: when the latest outputs came
  std::int64_t first_step_wall_ns_ = 0;                // HITL: when the first sensor step went
  std::string config_path_;  // the configuration file dut_emu reads at start; removed after
  std::ofstream tlog_file_;
  std::unique_ptr<mavlink::TlogWriter> tlog_;
  mavlink::FrameParser parser_{&mavlink::FindWireInfo};
  std::vector<std::uint8_t> unparsed_;  // read from the simulator link, not in the parser yet
  std::size_t unparsed_begin_ = 0;
  std::uint8_t sim_sequence_ = 0;
  std::uint8_t api_sequence_ = 0;

  std::int64_t now_ns_ = 0;  // the time of the last request, stamping the log
  std::optional<ImuMessage> imu_;
  std::vector<VioMessage> poses_;            // delivered since the last sensor step
  std::optional<SetpointMessage> setpoint_;  // a new setpoint not sent yet
  // The navigation sensors' readings since the last sensor step (the newest of each).
  std::optional<MagnetometerMessage> mag_;
  std::optional<BarometerMessage> baro_;
  std::optional<GnssMessage> fix_;
  // The offboard mode and the arming, from the first setpoint on, and the grasp since it last
  // changed, each until the DUT accepts it.
  struct Command {
    mavlink::CommandLong message;
    bool accepted = false;
    std::optional<std::int64_t> first_sent_ns;
    std::int64_t last_sent_ns = 0;
    std::optional<std::uint8_t> last_refusal;  // MAV_RESULT
  };
  static constexpr std::size_t kGraspCommand = 2;
  std::array<Command, 3> commands_;
  SetpointMessage grasp_;  // the grasp last commanded
  // The DUT's latest estimates, and whether a step's are due before its answer is taken.
  std::optional<mavlink::DebugFloatArray> telemetry_;
  bool estimates_due_ = false;
  bool setpoint_seen_ = false;
  std::uint64_t commands_refused_ = 0;
  std::int64_t next_heartbeat_ns_ = 0;
  // The request the next event answers: a tick between sensor steps (answered at once), or the
  // sensor step awaiting its HIL_ACTUATOR_CONTROLS.
  struct Awaited {
    std::uint64_t tick = 0;
    std::uint64_t time_usec = 0;
    bool immediate = false;
  };
  std::optional<Awaited> awaited_;
  mavlink::HilActuatorControls last_controls_;  // held between sensor steps
  std::uint64_t answered_tick_ = 0;             // of the last kAnswer
  bool answering_ = false;                      // the first HIL_ACTUATOR_CONTROLS came
  const rig::Clock* clock_ = nullptr;           // the session's, from Open
  std::int64_t answer_at_once_ns_ = 0;          // before the first answer: the step's give-up time
  std::uint64_t answered_at_once_usec_ = 0;     // the last step answered before it
  std::uint64_t late_answers_ = 0;

  std::uint64_t sensor_steps_ = 0;
  std::uint64_t odometry_sent_ = 0;
  std::uint64_t setpoints_sent_ = 0;
  std::uint64_t can_frames_sent_ = 0;
  std::uint64_t gps_sent_ = 0;
  std::uint64_t can_frames_not_carried_ = 0;  // CAN FD and error frames: CAN_FRAME has no room
  std::uint64_t telemetry_received_ = 0;
  std::uint64_t controls_received_ = 0;
  std::uint64_t frames_ignored_ = 0;  // well-formed frames that answer nothing
  std::uint64_t api_frames_received_ = 0;
  std::uint64_t tlog_records_ = 0;
};

}  // namespace hilrig::host
