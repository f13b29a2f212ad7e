#include "host/linked_dut/mavlink_dut_link.h"

#include <arpa/inet.h>
#include <stdlib.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "host/link/dut_config_codec.h"
#include "host/link/hil_link_socket.h"
#include "host/link/open_byte_stream.h"
#include "host/link/pseudo_terminal.h"
#include "host/linked_dut/linked_dut.h"
#include "host/linked_dut/peer_wait.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

constexpr std::uint8_t kSimSystem = 1;
constexpr std::uint8_t kSimComponent = 51;
constexpr std::uint8_t kApiSystem = 255;  // a ground station
constexpr std::uint8_t kApiComponent = 190;
constexpr float kCustomModeEnabled = 1;      // MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
constexpr float kPx4OffboardMode = 6;        // PX4_CUSTOM_MAIN_MODE_OFFBOARD
constexpr std::uint8_t kResultAccepted = 0;  // MAV_RESULT_ACCEPTED
constexpr std::int64_t kHeartbeatPeriodNs = 1'000'000'000;
constexpr std::int64_t kCommandRetryNs = 1'000'000'000;
constexpr int kWriteTimeoutMs = 1000;
constexpr int kTerminateGraceMs = 1000;
constexpr std::size_t kReadChunkBytes = 4096;

// The name of a command the link sends, for its errors.
const char* CommandName(std::uint16_t command) {
  switch (command) {
    case kMavCmdComponentArmDisarm:
      return "MAV_CMD_COMPONENT_ARM_DISARM";
    case kMavCmdDoSetMode:
      return "MAV_CMD_DO_SET_MODE";
    case kMavCmdDoGripper:
      return "MAV_CMD_DO_GRIPPER";
    default:
      return "MAV_CMD";
  }
}

// The first output of `controls` that is not a number, as the run's error.
std::optional<rig::Error> NonFiniteOutput(const mavlink::HilActuatorControls& controls) {
  for (std::size_t output = 0; output < controls.controls.size(); ++output) {
    if (!std::isfinite(controls.controls[output])) {
      return rig::MakeError("the dut sent a non-finite actuator output " + std::to_string(output) +
                            " at " + std::to_string(controls.time_usec) + " us");
    }
  }
  return std::nullopt;
}

bool Positive(double seconds) { return std::isfinite(seconds) && seconds > 0 && seconds <= 3600; }

}  // namespace

rig::Result<void> ValidateMavlinkDutOptions(const MavlinkDutOptions& options) {
  in_addr address{};
  if (::inet_pton(AF_INET, options.address.c_str(), &address) != 1) {
    return rig::MakeError("mavlink address \"" + options.address + "\": not an IPv4 address");
  }
  for (const auto& [seconds, what] : {std::pair{options.start_timeout_s, "start timeout"},
                                      std::pair{options.command_timeout_s, "command timeout"}}) {
    if (!Positive(seconds)) {
      return rig::MakeError(std::string("mavlink ") + what + " " + rig::NumberText(seconds) +
                            " s: must be positive, finite and at most an hour");
    }
  }
  if (!(options.first_answer_wait_s >= 0) || options.first_answer_wait_s > 1) {
    return rig::MakeError("mavlink first answer wait " +
                          rig::NumberText(options.first_answer_wait_s) +
                          " s: must be from 0 to 1 s");
  }
  if (options.hitl && !options.start_stand_in && options.serial_device.empty()) {
    return rig::MakeError("a MAVLink board needs its serial device");
  }
  if (options.hitl && options.baud < MavlinkDutOptions::kHitlMinimumBaud) {
    return rig::MakeError("baud " + std::to_string(options.baud) + " is too slow for HITL: the " +
                          "sensor steps, poses and setpoints need about 40 kB/s (at least " +
                          std::to_string(MavlinkDutOptions::kHitlMinimumBaud) + ")");
  }
  if (options.hitl &&
      !(Positive(options.controls_timeout_s) && Positive(options.first_controls_timeout_s))) {
    return rig::MakeError("mavlink controls timeout " +
                          rig::NumberText(options.controls_timeout_s) + " s: must be positive");
  }
  if (!Positive(options.sensor_period_s) || options.sensor_period_s > 1) {
    return rig::MakeError("mavlink sensor period " + rig::NumberText(options.sensor_period_s) +
                          " s: must be positive and at most 1 s");
  }
  return {};
}

MavlinkDutLink::MavlinkDutLink(const DutFirmware& firmware, double control_period_s,
                               const MavlinkDutOptions& options)
    : firmware_(firmware),
      control_period_s_(control_period_s),
      options_(options),
      scale_(ActuatorScaleOf(firmware)) {
  commands_[0].message.command = kMavCmdDoSetMode;
  commands_[0].message.param1 = kCustomModeEnabled;
  commands_[0].message.param2 = kPx4OffboardMode;
  commands_[1].message.command = kMavCmdComponentArmDisarm;
  commands_[1].message.param1 = 1;
  for (Command& command : commands_) {
    command.message.target_system = command.message.target_component = 1;
  }
  // The gripper starts open, as the DUT's: nothing to send until the scene grasps.
  commands_[kGraspCommand].message = GripperCommandFrom(grasp_);
  commands_[kGraspCommand].accepted = true;
  sensor_every_ticks_ = static_cast<std::uint64_t>(
      std::max<long long>(1, std::llround(options.sensor_period_s / control_period_s)));
}

MavlinkDutLink::~MavlinkDutLink() {
  if (!config_path_.empty()) ::unlink(config_path_.c_str());
}

void MavlinkDutLink::SetRunFolder(const std::string& folder) {
  if (!folder.empty()) options_.tlog_path = (std::filesystem::path(folder) / "mavlink.tlog");
}

rig::Result<std::string> MavlinkDutLink::WriteConfigFile() const {
  // The stand-in steps its controller once per sensor step.
  const double period_s = double(sensor_every_ticks_) * control_period_s_;
  const std::string bytes = ToDutConfig(firmware_, period_s).SerializeAsString();
  std::string path = (std::filesystem::temp_directory_path() / "hilrig-mavlink-XXXXXX").string();
  const int fd = ::mkstemp(path.data());
  if (fd < 0) return rig::MakeError("cannot create the dut's configuration file " + path);
  const bool written = ::write(fd, bytes.data(), bytes.size()) == ssize_t(bytes.size());
  ::close(fd);
  if (!written) {
    ::unlink(path.c_str());
    return rig::MakeError("cannot write the dut's configuration file " + path);
  }
  return path;
}

rig::Result<void> MavlinkDutLink::StartStandIn(std::vector<std::string> link_arguments) {
  std::string program = options_.dut_emu_path;
  if (program.empty()) {
    auto directory = ExecutableDirectory();
    if (!directory) return directory.error();
    program = (std::filesystem::path(directory.value()) / "dut_emu").string();
  }
  if (::access(program.c_str(), X_OK) != 0) {
    return rig::MakeError("no dut_emu executable at " + program + " (build the dut_emu target)");
  }
  auto config = WriteConfigFile();
  if (!config) return config.error();
  config_path_ = config.value();
  std::vector<std::string> argv = {program};
  argv.insert(argv.end(), link_arguments.begin(), link_arguments.end());
  argv.insert(argv.end(), {"--config", config_path_});
  argv.insert(argv.end(), options_.extra_args.begin(), options_.extra_args.end());
  auto child = ChildProcess::Spawn(argv);
  if (!child) return child.error();
  child_ = std::move(child).value();
  return {};
}

rig::Result<void> MavlinkDutLink::Open(const rig::Clock& clock) {
  if (auto valid = ValidateMavlinkDutOptions(options_); !valid) return valid.error();
  clock_ = &clock;
  const std::int64_t deadline_ns = clock.NowNs() + rig::NsFromSeconds(options_.start_timeout_s);
  if (!options_.tlog_path.empty()) {
    tlog_file_.open(options_.tlog_path, std::ios::binary | std::ios::trunc);
    if (!tlog_file_) return rig::MakeError("cannot write " + options_.tlog_path);
    tlog_ = std::make_unique<mavlink::TlogWriter>(tlog_file_);
  }
  auto opened =
      options_.hitl ? OpenSerialLine(clock, deadline_ns) : OpenSockets(clock, deadline_ns);
  if (!opened) return opened;
  opened_ = true;
  return {};
}

rig::Result<void> MavlinkDutLink::OpenSockets(const rig::Clock& clock, std::int64_t deadline_ns) {
  auto listener = LinkListener::Listen(options_.address, options_.sim_port);
  if (!listener) return listener.error();
  auto api = UdpSocket::Bind(options_.address, options_.api_port);
  if (!api) return api.error();
  api_ = std::move(api).value();
  const std::string sim_endpoint =
      options_.address + ":" + std::to_string(listener.value()->port());
  const std::string api_endpoint = options_.address + ":" + std::to_string(api_->port());
  if (options_.start_stand_in) {
    if (auto started = StartStandIn({"--mavlink", sim_endpoint, "--api", api_endpoint}); !started) {
      return started;
    }
  } else if (options_.notes != nullptr) {
    *options_.notes << "hilrig: waiting up to " << rig::SecondsText(options_.start_timeout_s)
                    << " for a flight stack on the MAVLink simulator link tcp " << sim_endpoint
                    << " and its heartbeat on the API link udp " << api_endpoint
                    << " (docs/px4.md)\n";
  }
  const PeerWait wait{&clock, deadline_ns, child_ ? &*child_ : nullptr, options_.stop_requested};
  auto accepted = WaitForPeer(
      wait,
      [&](int slice_ms) -> std::optional<rig::Result<LinkListener::AcceptedStream>> {
        auto stream = listener.value()->AcceptStream(slice_ms);
        if (!stream && stream.error().code == rig::ErrorCode::kTimeout) return std::nullopt;
        return stream;
      },
      [&](const PeerWaitFailure& failure) -> rig::Result<LinkListener::AcceptedStream> {
        switch (failure.end) {
          case PeerWaitEnd::kStopped:
            return rig::MakeError(rig::ErrorCode::kInterrupted,
                                  "stopped while waiting for the dut");
          case PeerWaitEnd::kPeerExited:
            return rig::MakeError("the dut's PX4 stand-in " + failure.exit +
                                  " before it connected");
          case PeerWaitEnd::kTimedOut:
            break;
        }
        return rig::MakeError(rig::ErrorCode::kTimeout,
                              "no flight stack connected to tcp " + sim_endpoint + " within " +
                                  rig::SecondsText(options_.start_timeout_s));
      });
  if (!accepted) return accepted.error();
  sim_ = std::move(accepted.value().stream);
  // The stand-in read its configuration before it dialled.
  if (!config_path_.empty()) ::unlink(config_path_.c_str());
  config_path_.clear();
  return AwaitPeer(clock, deadline_ns);
}

rig::Result<void> MavlinkDutLink::OpenSerialLine(const rig::Clock& clock,
                                                 std::int64_t deadline_ns) {
  std::string where = options_.serial_device;
  if (options_.start_stand_in) {
    auto pair = OpenPseudoTerminal();
    if (!pair) return pair.error();
    sim_ = std::move(pair.value().master);
    slave_hold_ = std::move(pair.value().slave_hold);
    where = pair.value().slave_path;
    if (auto started = StartStandIn({"--mavlink-serial", where}); !started) return started;
  } else {
    auto port = OpenSerialPort(options_.serial_device, options_.baud);
    if (!port) return port.error();
    sim_ = std::move(port).value();
    if (options_.notes != nullptr) {
      *options_.notes << "hilrig: waiting up to " << rig::SecondsText(options_.start_timeout_s)
                      << " for a flight stack's heartbeat on " << sim_->name()
                      << " (docs/px4.md)\n";
    }
  }
  auto heard = AwaitHeartbeat(clock, deadline_ns, "on " + where,
                              [&](int slice_ms) -> std::optional<rig::Result<void>> {
                                auto next = NextSimFrame(slice_ms);
                                if (!next) return rig::Result<void>(next.error());
                                if (!next.value()) return std::nullopt;
                                LogReceived(*next.value());
                                if (next.value()->message_id != mavlink::Heartbeat::kId) {
                                  return std::nullopt;
                                }
                                return rig::Result<void>();
                              });
  if (!heard) return heard;
  line_name_ = sim_->name();
  // The stand-in holds the line's far end now.
  slave_hold_.reset();
  if (!config_path_.empty()) ::unlink(config_path_.c_str());
  config_path_.clear();
  return {};
}

rig::Result<void> MavlinkDutLink::AwaitPeer(const rig::Clock& clock, std::int64_t deadline_ns) {
  std::array<std::uint8_t, mavlink::kMaxSignedFrameBytes> datagram;
  return AwaitHeartbeat(clock, deadline_ns, "to the API port " + std::to_string(api_->port()),
                        [&](int slice_ms) -> std::optional<rig::Result<void>> {
                          auto got = api_->Receive(datagram, slice_ms);
                          if (!got) return rig::Result<void>(got.error());
                          if (!got.value()) return std::nullopt;
                          ++api_frames_received_;
                          Log(std::span(datagram.data(), *got.value()));
                          return rig::Result<void>();
                        });
}

rig::Result<void> MavlinkDutLink::AwaitHeartbeat(const rig::Clock& clock, std::int64_t deadline_ns,
                                                 const std::string& where,
                                                 const HeartbeatProbe& probe) {
  const PeerWait wait{&clock, deadline_ns, child_ ? &*child_ : nullptr, options_.stop_requested};
  return WaitForPeer(wait, probe, [&](const PeerWaitFailure& failure) -> rig::Result<void> {
    switch (failure.end) {
      case PeerWaitEnd::kStopped:
        return rig::MakeError(rig::ErrorCode::kInterrupted,
                              "stopped while waiting for the dut's heartbeat");
      case PeerWaitEnd::kPeerExited:
        return rig::MakeError("the dut's PX4 stand-in " + failure.exit + " before its heartbeat");
      case PeerWaitEnd::kTimedOut:
        break;
    }
    return rig::MakeError(rig::ErrorCode::kTimeout, "the dut sent no heartbeat " + where +
                                                        " within " +
                                                        rig::SecondsText(options_.start_timeout_s));
  });
}

std::optional<std::string> MavlinkDutLink::PeerExit() {
  if (!child_) return std::nullopt;
  auto exit = child_->PollExit();
  if (!exit) return std::nullopt;
  if (child_->exit_status() == kStandInExitSensorsStale) {
    return "the dut's PX4 stand-in found its IMU readings stale, as PX4 would (they repeated "
           "exactly): the scene needs IMU noise";
  }
  return "the dut's PX4 stand-in " + *exit;
}

void MavlinkDutLink::Close(bool) {
  // MAVLink has no goodbye: the stand-in ends with the simulator link, PX4 waits for the next.
  sim_.reset();
  if (child_) child_->Terminate(kTerminateGraceMs);
  if (tlog_file_.is_open()) tlog_file_.flush();
}

void MavlinkDutLink::LogReceived(const mavlink::Frame& frame) {
  // The frame as it was checked, re-encoded: what a sender trims differently reads the same.
  const mavlink::MessageInfo* info = mavlink::FindMessage(frame.message_id);
  std::array<std::uint8_t, mavlink::kMaxFrameBytes> bytes;
  const std::size_t size = info ? mavlink::EncodeFrame(frame, info->crc_extra, bytes) : 0;
  if (size > 0) Log(std::span(bytes.data(), size));
}

void MavlinkDutLink::Log(std::span<const std::uint8_t> frame) {
  if (!tlog_) return;
  if (tlog_->Write(MavlinkTimeUs(now_ns_), frame)) ++tlog_records_;
}

rig::Result<void> MavlinkDutLink::SendSim(const mavlink::AnyMessage& message) {
  std::array<std::uint8_t, mavlink::kMaxFrameBytes> frame;
  const std::size_t size =
      mavlink::EncodeMessage(message, sim_sequence_++, kSimSystem, kSimComponent, frame);
  Log(std::span(frame.data(), size));
  if (auto written = sim_->WriteAll(std::span(frame.data(), size), kWriteTimeoutMs); !written) {
    return rig::MakeError(written.error().code,
                          "the mavlink simulator link: " + written.error().message);
  }
  return {};
}

rig::Result<void> MavlinkDutLink::SendApi(const mavlink::AnyMessage& message) {
  std::array<std::uint8_t, mavlink::kMaxFrameBytes> frame;
  const std::size_t size =
      mavlink::EncodeMessage(message, api_sequence_++, kApiSystem, kApiComponent, frame);
  Log(std::span(frame.data(), size));
  if (api_ == nullptr) {
    // HITL: the ground station's frames share the board's serial line.
    if (auto written = sim_->WriteAll(std::span(frame.data(), size), kWriteTimeoutMs); !written) {
      return rig::MakeError(written.error().code, "the mavlink line: " + written.error().message);
    }
    return {};
  }
  return api_->Send(std::span(frame.data(), size));
}

rig::Result<void> MavlinkDutLink::Input(const DutInput& input, bool, std::int64_t) {
  if (const auto* imu = std::get_if<ImuMessage>(&input)) {
    imu_ = *imu;
  } else if (const auto* vio = std::get_if<VioMessage>(&input)) {
    poses_.push_back(*vio);
  } else if (const auto* mag = std::get_if<MagnetometerMessage>(&input)) {
    mag_ = *mag;
  } else if (const auto* baro = std::get_if<BarometerMessage>(&input)) {
    baro_ = *baro;
  } else if (const auto* fix = std::get_if<GnssMessage>(&input)) {
    fix_ = *fix;
  } else if (const auto* setpoint = std::get_if<SetpointMessage>(&input)) {
    setpoint_ = *setpoint;
    if (!SameGrasp(*setpoint, grasp_)) {
      grasp_ = *setpoint;
      commands_[kGraspCommand] = Command();
      commands_[kGraspCommand].message = GripperCommandFrom(*setpoint);
    }
  }
  return {};
}

rig::Result<void> MavlinkDutLink::Request(const LinkRequest& request) {
  now_ns_ = request.now_ns;
  if (request.frames != nullptr) {
    if (auto sent = ForwardCanFrames(*request.frames); !sent) return sent;
  }
  const std::uint64_t time_usec = MavlinkTimeUs(request.now_ns);
  // PX4 takes a time of 0 for no time at all: the first sensor step comes after it.
  if (request.tick % sensor_every_ticks_ != 0 || !imu_ || time_usec == 0) {
    awaited_ = Awaited{request.tick, 0, true};
    return {};
  }
  const std::uint32_t time_boot_ms = static_cast<std::uint32_t>(time_usec / 1000);
  if (request.now_ns >= next_heartbeat_ns_) {
    mavlink::Heartbeat heartbeat;
    heartbeat.type = 6;           // MAV_TYPE_GCS
    heartbeat.autopilot = 8;      // MAV_AUTOPILOT_INVALID
    heartbeat.system_status = 4;  // MAV_STATE_ACTIVE
    if (auto sent = SendApi(heartbeat); !sent) return sent;
    next_heartbeat_ns_ = request.now_ns + kHeartbeatPeriodNs;
    // Once a second of the run the log reaches the disk: a run killed outright keeps it to there.
    if (tlog_file_.is_open()) tlog_file_.flush();
  }
  if (setpoint_) {
    if (auto sent = SendApi(PositionTargetFrom(*setpoint_, time_boot_ms)); !sent) return sent;
    ++setpoints_sent_;
    setpoint_.reset();
    setpoint_seen_ = true;
  }
  if (auto sent = SendCommandsDue(); !sent) return sent;
  for (const VioMessage& pose : poses_) {
    if (auto sent = SendSim(OdometryFrom(pose)); !sent) return sent;
    ++odometry_sent_;
  }
  poses_.clear();
  if (fix_) {
    if (auto sent = SendSim(HilGpsFrom(*fix_, kRunEpochUnixUsec + time_usec)); !sent) return sent;
    ++gps_sent_;
    fix_.reset();
  }
  // A magnetometer or barometer reading goes with the first sensor step after it, once.
  const MagnetometerMessage* mag = mag_ ? &*mag_ : nullptr;
  const BarometerMessage* baro = baro_ ? &*baro_ : nullptr;
  if (auto sent = SendSim(HilSensorFrom(*imu_, time_usec, mag, baro)); !sent) return sent;
  mag_.reset();
  baro_.reset();
  ++sensor_steps_;
  // A board answers on its own clock: every tick is answered at once with its latest outputs.
  awaited_ = Awaited{request.tick, time_usec, options_.hitl};
  if (options_.hitl && sensor_steps_ == 1) first_step_wall_ns_ = clock_->NowNs();
  // Only a booting flight stack's step has a give-up time: the lockstep tick reads no clock.
  if (options_.first_answers_late && !answering_) {
    answer_at_once_ns_ = clock_->NowNs() + rig::NsFromSeconds(options_.first_answer_wait_s);
  }
  return {};
}

rig::Result<void> MavlinkDutLink::ForwardCanFrames(const std::vector<rig::TimedCanFrame>& frames) {
  for (const rig::TimedCanFrame& timed : frames) {
    const std::optional<mavlink::CanFrame> message = CanFrameMessageFrom(timed.frame);
    if (!message) {
      ++can_frames_not_carried_;
      continue;
    }
    if (auto sent = SendSim(*message); !sent) return sent;
    ++can_frames_sent_;
  }
  return {};
}

rig::Result<void> MavlinkDutLink::SendCommandsDue() {
  if (!setpoint_seen_) return {};
  for (Command& command : commands_) {
    if (command.accepted) continue;
    if (command.first_sent_ns && now_ns_ - command.last_sent_ns < kCommandRetryNs) continue;
    if (auto sent = SendApi(command.message); !sent) return sent;
    if (!command.first_sent_ns) command.first_sent_ns = now_ns_;
    command.last_sent_ns = now_ns_;
  }
  return {};
}

rig::Result<void> MavlinkDutLink::DrainApi() {
  if (api_ == nullptr) return {};  // HITL: the line's frames are read as they come
  std::array<std::uint8_t, mavlink::kMaxSignedFrameBytes> datagram;
  while (true) {
    auto got = api_->Receive(datagram, 0);
    if (!got) return got.error();
    if (!got.value()) return {};
    ++api_frames_received_;
    const std::span<const std::uint8_t> bytes(datagram.data(), *got.value());
    Log(bytes);
    mavlink::FrameParser parser(&mavlink::FindWireInfo);
    parser.Feed(bytes, [&](const mavlink::Frame& frame) {
      if (const auto message = mavlink::DecodeMessage(frame)) TakeApiMessage(*message);
    });
  }
}

void MavlinkDutLink::TakeApiMessage(const mavlink::AnyMessage& message) {
  if (const auto* array = std::get_if<mavlink::DebugFloatArray>(&message)) {
    if (!IsTelemetry(*array)) return;
    telemetry_ = *array;
    ++telemetry_received_;
    return;
  }
  const auto* ack = std::get_if<mavlink::CommandAck>(&message);
  if (ack == nullptr) return;
  for (Command& command : commands_) {
    if (command.message.command != ack->command || command.accepted) continue;
    command.accepted = ack->result == kResultAccepted;
    if (!command.accepted) {
      command.last_refusal = ack->result;
      ++commands_refused_;
    }
  }
}

std::optional<rig::Error> MavlinkDutLink::CommandOverdue() const {
  for (const Command& command : commands_) {
    if (command.accepted || !command.first_sent_ns) continue;
    if (now_ns_ - *command.first_sent_ns < rig::NsFromSeconds(options_.command_timeout_s)) continue;
    const std::string what = "command " + std::to_string(command.message.command) + " (" +
                             CommandName(command.message.command) + ")";
    return rig::MakeError(command.last_refusal
                              ? "the dut refused " + what + " for " +
                                    rig::SecondsText(options_.command_timeout_s) +
                                    " of the run (last answer MAV_RESULT " +
                                    std::to_string(*command.last_refusal) + ")"
                              : "the dut did not acknowledge " + what + " within " +
                                    rig::SecondsText(options_.command_timeout_s) + " of the run");
  }
  return std::nullopt;
}

rig::Result<std::optional<mavlink::Frame>> MavlinkDutLink::NextSimFrame(int timeout_ms) {
  while (true) {
    if (auto frame = parser_.Next()) return frame;
    // The parser holds two frames' worth; what it has no room for yet waits here. Once Next()
    // finds nothing, at least a frame's worth fits, so each pass makes progress.
    if (unparsed_begin_ < unparsed_.size()) {
      unparsed_begin_ += parser_.Push(std::span(unparsed_).subspan(unparsed_begin_));
      continue;
    }
    unparsed_.resize(kReadChunkBytes);
    unparsed_begin_ = 0;
    const StreamRead read = sim_->ReadSome(unparsed_, timeout_ms);
    unparsed_.resize(read.status == StreamStatus::kData ? read.bytes : 0);
    switch (read.status) {
      case StreamStatus::kTimeout:
        return std::optional<mavlink::Frame>();
      case StreamStatus::kClosed:
        return rig::MakeError(rig::ErrorCode::kLinkClosed, "the dut closed the mavlink link");
      case StreamStatus::kError:
        return rig::MakeError(rig::ErrorCode::kIo, "the mavlink link failed: " + read.error);
      case StreamStatus::kData:
        break;
    }
  }
}

DutLinkEvent MavlinkDutLink::ReceiveHitl() {
  while (true) {
    auto next = NextSimFrame(0);
    if (!next) {
      const bool closed = next.error().code == rig::ErrorCode::kLinkClosed ||
                          next.error().code == rig::ErrorCode::kIo;
      return {closed ? DutLinkEventKind::kClosed : DutLinkEventKind::kFailed, 0, next.error()};
    }
    if (!next.value()) break;
    const mavlink::Frame& frame = *next.value();
    LogReceived(frame);
    const auto message = mavlink::DecodeMessage(frame);
    if (!message) continue;
    if (const auto* controls = std::get_if<mavlink::HilActuatorControls>(&*message)) {
      if (auto bad = NonFiniteOutput(*controls)) return {DutLinkEventKind::kFailed, 0, *bad};
      ++controls_received_;
      last_controls_ = *controls;
      last_controls_wall_ns_ = clock_->NowNs();
      continue;
    }
    ++api_frames_received_;
    TakeApiMessage(*message);
  }
  if (auto overdue = CommandOverdue()) return {DutLinkEventKind::kFailed, 0, *overdue};
  const std::int64_t now_ns = clock_->NowNs();
  const double limit_s =
      last_controls_wall_ns_ ? options_.controls_timeout_s : options_.first_controls_timeout_s;
  std::optional<std::int64_t> since_ns = last_controls_wall_ns_;
  if (!since_ns && sensor_steps_ > 0) since_ns = first_step_wall_ns_;
  if (since_ns && now_ns - *since_ns > rig::NsFromSeconds(limit_s)) {
    return {DutLinkEventKind::kFailed, 0,
            rig::MakeError(std::string("the board sent no HIL_ACTUATOR_CONTROLS for ") +
                           rig::SecondsText(limit_s) +
                           (last_controls_wall_ns_ ? "" : " after the first sensor step"))};
  }
  if (!awaited_) return {};
  answered_tick_ = awaited_->tick;
  awaited_.reset();
  estimates_due_ = false;
  return {DutLinkEventKind::kAnswer, answered_tick_, std::nullopt};
}

DutLinkEvent MavlinkDutLink::Receive(int timeout_ms) {
  if (options_.hitl) return ReceiveHitl();
  // A tick between sensor steps is answered without a look at either socket.
  if (awaited_ && awaited_->immediate) {
    answered_tick_ = awaited_->tick;
    awaited_.reset();
    return {DutLinkEventKind::kAnswer, answered_tick_, std::nullopt};
  }
  if (auto drained = DrainApi(); !drained) {
    return {DutLinkEventKind::kClosed, 0, drained.error()};
  }
  if (auto overdue = CommandOverdue()) return {DutLinkEventKind::kFailed, 0, *overdue};
  // Before the first answer, a flight stack that answers late is waited for a little only.
  const bool booting = options_.first_answers_late && !answering_ && awaited_;
  const std::int64_t left_ns = booting ? answer_at_once_ns_ - clock_->NowNs() : 0;
  const bool at_once = booting && left_ns <= 0;
  const int wait_ms =
      booting ? std::min<int>(timeout_ms, int(std::max<std::int64_t>(0, left_ns) / 1'000'000))
              : timeout_ms;
  auto next = NextSimFrame(wait_ms);
  if (!next) {
    const bool closed = next.error().code == rig::ErrorCode::kLinkClosed ||
                        next.error().code == rig::ErrorCode::kIo;
    return {closed ? DutLinkEventKind::kClosed : DutLinkEventKind::kFailed, 0, next.error()};
  }
  if (!next.value()) {
    if (!at_once) return {};  // booting: the next look may be past the give-up time
    answered_at_once_usec_ = awaited_->time_usec;
    answered_tick_ = awaited_->tick;
    awaited_.reset();
    return {DutLinkEventKind::kAnswer, answered_tick_, std::nullopt};
  }
  const mavlink::Frame& frame = *next.value();
  LogReceived(frame);
  const auto message = mavlink::DecodeMessage(frame);
  const auto* controls = message ? std::get_if<mavlink::HilActuatorControls>(&*message) : nullptr;
  if (!controls) {
    ++frames_ignored_;
    return {DutLinkEventKind::kIgnored, 0, std::nullopt};
  }
  return Answer(*controls);
}

DutLinkEvent MavlinkDutLink::Answer(const mavlink::HilActuatorControls& controls) {
  ++controls_received_;
  answering_ = true;
  if (auto bad = NonFiniteOutput(controls)) return {DutLinkEventKind::kFailed, 0, *bad};
  if (controls.time_usec != 0 && controls.time_usec <= answered_at_once_usec_) {
    // A late answer to a step answered at once: the vehicle's outputs from now on.
    ++late_answers_;
    last_controls_ = controls;
    return {DutLinkEventKind::kIgnored, 0, std::nullopt};
  }
  if (!awaited_ || controls.time_usec != awaited_->time_usec) {
    return {DutLinkEventKind::kFailed, 0,
            rig::MakeError("the dut answered time " + std::to_string(controls.time_usec) +
                           " us, which no HIL_SENSOR asked for (" +
                           (awaited_ ? "awaited: " + std::to_string(awaited_->time_usec) + " us"
                                     : std::string("none awaited")) +
                           ")")};
  }
  last_controls_ = controls;
  answered_tick_ = awaited_->tick;
  awaited_.reset();
  estimates_due_ = true;
  return {DutLinkEventKind::kAnswer, answered_tick_, std::nullopt};
}

rig::Result<ActuatorMessage> MavlinkDutLink::TakeAnswer(std::int64_t arrival_wall_ns) {
  // A flight stack sends a step's estimates ahead of its answer; they are on the API link now.
  if (estimates_due_) {
    estimates_due_ = false;
    if (auto drained = DrainApi(); !drained) return drained.error();
  }
  ActuatorMessage command = ActuatorFrom(last_controls_, scale_);
  if (telemetry_) ApplyTelemetry(*telemetry_, command);
  command.stamp = {answered_tick_, arrival_wall_ns};
  command.answers_sequence = answered_tick_;
  return command;
}

std::string MavlinkDutLink::timeout_detail() const {
  const mavlink::ParserCounters& parsed = parser_.counters();
  const std::uint64_t broken = parsed.bytes_skipped + parsed.crc_failures + parsed.bad_lengths +
                               parsed.unknown_message_ids + parsed.unsupported_incompat_flags;
  if (broken == 0) return {};
  return " (it sent " + std::to_string(broken) + " bytes or frames that were no MAVLink frame " +
         "the rig could check: " + std::to_string(parsed.crc_failures) + " checksum failures, " +
         std::to_string(parsed.bytes_skipped) + " bytes skipped)";
}

std::string MavlinkDutLink::description() const {
  std::string text =
      options_.start_stand_in
          ? (options_.hitl ? "PX4's stand-in (dut_emu --mavlink-serial) on a serial line"
                           : "PX4's stand-in (dut_emu --mavlink) over MAVLink")
          : (options_.hitl ? "a flight stack on a board over MAVLink (PX4 HITL)"
                           : "a flight stack on the MAVLink simulator link (PX4 SITL)");
  if (!opened_) return text + " (not started)";
  if (child_) text += " (pid " + std::to_string(child_->pid()) + ")";
  text += ", HIL_SENSOR every " + std::to_string(sensor_every_ticks_) + " control ticks";
  if (api_ == nullptr) return text + ", both links on " + line_name_ + ", in real time";
  text += ", API link on udp " + std::to_string(api_->port()) + " to " + api_->peer();
  return text;
}

std::vector<rig::Metric> MavlinkDutLink::metrics(bool) const {
  if (!opened_) return {};
  std::vector<rig::Metric> metrics;
  const mavlink::ParserCounters& parsed = parser_.counters();
  for (const auto& [name, value] : {std::pair{"mavlink_sensor_steps", sensor_steps_},
                                    {"mavlink_odometry_sent", odometry_sent_},
                                    {"mavlink_setpoints_sent", setpoints_sent_},
                                    {"mavlink_can_frames_sent", can_frames_sent_},
                                    {"mavlink_gps_sent", gps_sent_},
                                    {"mavlink_can_frames_not_carried", can_frames_not_carried_},
                                    {"mavlink_estimates_received", telemetry_received_},
                                    {"mavlink_controls_received", controls_received_},
                                    {"mavlink_frames_ignored", frames_ignored_},
                                    {"mavlink_api_frames_received", api_frames_received_},
                                    {"mavlink_commands_refused", commands_refused_},
                                    {"mavlink_late_answers", late_answers_},
                                    {"mavlink_tlog_records", tlog_records_},
                                    {"mavlink_rx_frames", parsed.frames_ok},
                                    {"mavlink_rx_crc_failures", parsed.crc_failures},
                                    {"mavlink_rx_bytes_skipped", parsed.bytes_skipped},
                                    {"mavlink_rx_unknown_ids", parsed.unknown_message_ids},
                                    {"mavlink_rx_bad_lengths", parsed.bad_lengths}}) {
    metrics.push_back(rig::CountMetric(name, value));
  }
  return metrics;
}

}  // namespace hilrig::host
