#include "dut_emu/mavlink_dut.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <tuple>
#include <type_traits>
#include <utility>

#include "dut_emu/mavlink_serial_dut.h"
#include "dut_link/posix/line_io.h"
#include "host/dut/in_process_dut.h"
#include "host/link/open_byte_stream.h"
#include "proto/hil_link.pb.h"
#include "rig/check.h"
#include "rig/command_args.h"

namespace hilrig::dut_emu {
namespace {

namespace mav = ::hilrig::mavlink;

// MAVLink enum values this DUT speaks.
constexpr std::uint8_t kMavTypeQuadrotor = 2;
constexpr std::uint8_t kMavAutopilotPx4 = 12;
constexpr std::uint8_t kMavStateStandby = 3;
constexpr std::uint8_t kMavStateActive = 4;
constexpr std::uint8_t kModeFlagCustomModeEnabled = 1;
constexpr std::uint8_t kModeFlagSafetyArmed = 128;

// The rig's time is int64 nanoseconds; a time_usec past this does not fit.
constexpr std::uint64_t kMaxTimeUsec =
    static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max() / 1000);

std::int64_t NsFromUsec(std::uint64_t time_usec) {
  return static_cast<std::int64_t>(time_usec) * 1000;
}

bool AddressedToUs(std::uint8_t target_system, std::uint8_t target_component) {
  // 0 is MAVLink's broadcast for both.
  return (target_system == 0 || target_system == MavlinkDut::kSystemId) &&
         (target_component == 0 || target_component == MavlinkDut::kComponentId);
}

// A MAVLink command parameter that must be a small whole number (a flag set, a mode number).
std::optional<std::uint8_t> SmallWholeNumber(float param) {
  if (!std::isfinite(param) || param < 0 || param > 255) return std::nullopt;
  const float rounded = std::round(param);
  if (rounded != param) return std::nullopt;
  return static_cast<std::uint8_t>(rounded);
}

}  // namespace

bool MavlinkFrameBatch::Append(const mavlink::AnyMessage& message, std::uint8_t sequence,
                               std::uint8_t system_id, std::uint8_t component_id) {
  if (frames_ == kMaxFrames) return false;
  const std::size_t size =
      mav::EncodeMessage(message, sequence, system_id, component_id, storage_[frames_]);
  if (size == 0) return false;
  sizes_[frames_++] = size;
  return true;
}

MavlinkDut::MavlinkDut(const host::DutFirmware& firmware, double control_period_s)
    : range_(host::ActuatorScaleOf(firmware)) {
  auto bus = std::make_unique<LinkCanBus>();
  can_ = bus.get();
  port_ = std::make_unique<host::InProcessDut>(firmware, std::move(bus), control_period_s);
}

MavlinkDut::MavlinkDut(std::unique_ptr<host::DutPort> port, const host::ActuatorScale& range)
    : port_(std::move(port)), range_(range) {}

void MavlinkDut::Begin() {
  replies_.simulator.Clear();
  replies_.api.Clear();
}

const MavlinkReplies& MavlinkDut::End(MavlinkDutEnd end, std::string why) {
  replies_.end = end;
  replies_.why = std::move(why);
  return replies_;
}

void MavlinkDut::Send(MavlinkLink link, const mavlink::AnyMessage& message) {
  const auto index = static_cast<std::size_t>(link);
  MavlinkFrameBatch& batch = link == MavlinkLink::kSimulator ? replies_.simulator : replies_.api;
  const bool appended = batch.Append(message, sequence_[index], kSystemId, kComponentId);
  HILRIG_CHECK(appended, "more replies to one input than a MavlinkFrameBatch holds");
  ++sequence_[index];
}

const MavlinkReplies& MavlinkDut::Announce() {
  Begin();
  if (replies_.end == MavlinkDutEnd::kRunning) Send(MavlinkLink::kApi, MakeHeartbeat());
  return replies_;
}

const MavlinkReplies& MavlinkDut::HandleFrame(const mavlink::Frame& frame, MavlinkLink link) {
  Begin();
  if (replies_.end != MavlinkDutEnd::kRunning) return replies_;
  const std::optional<mavlink::AnyMessage> message = mav::DecodeMessage(frame);
  if (!message) {
    return End(MavlinkDutEnd::kUndecodable,
               "a frame of message id " + std::to_string(frame.message_id) + " on the " +
                   (link == MavlinkLink::kSimulator ? "simulator" : "API") +
                   " link does not decode");
  }
  return Handle(*message, link, MavlinkSender{frame.system_id, frame.component_id});
}

const MavlinkReplies& MavlinkDut::Handle(const mavlink::AnyMessage& message, MavlinkLink link,
                                         MavlinkSender sender) {
  Begin();
  if (replies_.end != MavlinkDutEnd::kRunning) return replies_;
  const bool simulator = link == MavlinkLink::kSimulator;
  if (const auto* sensor = std::get_if<mavlink::HilSensor>(&message); sensor && simulator) {
    HandleSensor(*sensor);
  } else if (const auto* odometry = std::get_if<mavlink::Odometry>(&message);
             odometry && simulator) {
    HandleOdometry(*odometry);
  } else if (const auto* can = std::get_if<mavlink::CanFrame>(&message); can && simulator) {
    HandleCanFrame(*can);
  } else if (const auto* gps = std::get_if<mavlink::HilGps>(&message); gps && simulator) {
    HandleGps(*gps);
  } else if (const auto* command = std::get_if<mavlink::CommandLong>(&message);
             command && !simulator) {
    HandleCommand(*command, sender);
  } else if (const auto* target = std::get_if<mavlink::SetPositionTargetLocalNed>(&message);
             target && !simulator) {
    HandleSetpoint(*target);
  } else if (std::holds_alternative<mavlink::Heartbeat>(message)) {
    ++counters_.heartbeats_received;
  } else {
    ++counters_.ignored;
  }
  return replies_;
}

bool MavlinkDut::RepeatsStale(const mavlink::HilSensor& sensor) {
  // Bits, not values: a repeat is the very same reading, and NaN never equals itself.
  const std::array<std::uint32_t, 6> bits = {std::bit_cast<std::uint32_t>(sensor.xacc_m_s2),
                                             std::bit_cast<std::uint32_t>(sensor.yacc_m_s2),
                                             std::bit_cast<std::uint32_t>(sensor.zacc_m_s2),
                                             std::bit_cast<std::uint32_t>(sensor.xgyro_rad_s),
                                             std::bit_cast<std::uint32_t>(sensor.ygyro_rad_s),
                                             std::bit_cast<std::uint32_t>(sensor.zgyro_rad_s)};
  if (repeats_ > 0 && bits == last_reading_bits_) {
    ++repeats_;
  } else {
    last_reading_bits_ = bits;
    repeats_ = 1;
  }
  return repeats_ >= kStaleRepeats;
}

void MavlinkDut::HandleSensor(const mavlink::HilSensor& sensor) {
  const std::uint64_t time_usec = sensor.time_usec;
  if (time_usec == 0) {
    End(MavlinkDutEnd::kTimeZero, "HIL_SENSOR with time_usec 0: the DUT's time starts after 0");
    return;
  }
  if (time_usec > kMaxTimeUsec) {
    End(MavlinkDutEnd::kTimeOutOfRange,
        "HIL_SENSOR time_usec " + std::to_string(time_usec) + " is past the rig's time range");
    return;
  }
  if (last_time_usec_ && time_usec <= *last_time_usec_) {
    End(MavlinkDutEnd::kTimeNotAdvancing, "HIL_SENSOR time_usec " + std::to_string(time_usec) +
                                              " does not come after the previous one, " +
                                              std::to_string(*last_time_usec_));
    return;
  }
  if (RepeatsStale(sensor)) {
    End(MavlinkDutEnd::kSensorsStale,
        "the accelerometer and gyro readings repeated " + std::to_string(kStaleRepeats) +
            " times: sensors stale (PX4 marks such a sensor stale; the scene needs IMU noise)");
    return;
  }
  last_time_usec_ = time_usec;
  const std::int64_t now_ns = NsFromUsec(time_usec);
  // What came since the last step reaches the controller now, stamped with this step's time.
  for (std::size_t i = 0; i < poses_held_; ++i) {
    poses_[i].stamp = {vio_sequence_++, now_ns};
    port_->Send(poses_[i]);
    ++counters_.poses;
  }
  poses_held_ = 0;
  if (setpoint_held_) {
    setpoint_held_->stamp = {setpoint_sequence_++, now_ns};
    port_->Send(*setpoint_held_);
    setpoint_held_.reset();
  }
  if (fix_held_) {
    fix_held_->stamp = {gnss_sequence_++, now_ns};
    port_->Send(*fix_held_);
    fix_held_.reset();
  }
  if (std::optional<host::MagnetometerMessage> mag = host::MagnetometerFrom(sensor)) {
    mag->stamp = {mag_sequence_++, now_ns};
    port_->Send(*mag);
  }
  if (std::optional<host::BarometerMessage> baro = host::BarometerFrom(sensor)) {
    baro->stamp = {baro_sequence_++, now_ns};
    port_->Send(*baro);
  }
  host::ImuMessage imu = host::ImuFrom(sensor);
  imu.stamp = {imu_sequence_++, now_ns};
  port_->Send(imu);
  const std::uint64_t tick = ++tick_;
  const rig::Result<host::ActuatorMessage> command = port_->Step(tick, now_ns);
  if (!command) {
    End(MavlinkDutEnd::kStepFailed,
        "the controller refused step " + std::to_string(tick) + ": " + command.error().message);
    return;
  }
  ++counters_.sensor_steps;
  if (time_usec >= next_heartbeat_usec_) {
    Send(MavlinkLink::kApi, MakeHeartbeat());
    next_heartbeat_usec_ = (time_usec / kHeartbeatPeriodUsec + 1) * kHeartbeatPeriodUsec;
  }
  // The estimates go ahead of the answer, so the rig holds this step's when the answer comes.
  Send(MavlinkLink::kApi, host::TelemetryFrom(command.value(), time_usec));
  Send(MavlinkLink::kSimulator, MakeControls(time_usec, command.value()));
}

void MavlinkDut::HandleOdometry(const mavlink::Odometry& odometry) {
  std::optional<host::VioMessage> vio = host::VioFrom(odometry);
  if (!vio) {
    ++counters_.ignored;
    return;
  }
  if (poses_held_ == poses_.size()) {
    End(MavlinkDutEnd::kTooManyPoses,
        "more than " + std::to_string(kMaxPosesPerStep) + " ODOMETRY before one HIL_SENSOR");
    return;
  }
  poses_[poses_held_++] = *vio;
}

void MavlinkDut::HandleSetpoint(const mavlink::SetPositionTargetLocalNed& target) {
  if (!AddressedToUs(target.target_system, target.target_component)) {
    ++counters_.ignored;
    return;
  }
  const std::optional<host::SetpointMessage> setpoint = host::SetpointFrom(target, last_setpoint_);
  if (!setpoint) {
    ++counters_.ignored;
    return;
  }
  // The newest wins, as a flight stack follows the latest offboard setpoint.
  last_setpoint_ = *setpoint;
  setpoint_held_ = *setpoint;
  ++counters_.setpoints;
}

void MavlinkDut::HandleCanFrame(const mavlink::CanFrame& message) {
  const std::optional<rig::CanFrame> frame = host::CanFrameFrom(message);
  if (can_ == nullptr || !frame ||
      !AddressedToUs(message.target_system, message.target_component)) {
    ++counters_.ignored;
    return;
  }
  can_->Deliver(std::span(&*frame, 1));
  ++counters_.can_frames;
}

void MavlinkDut::HandleGps(const mavlink::HilGps& gps) {
  std::optional<host::GnssMessage> fix = host::GnssFrom(gps);
  if (!fix) {
    ++counters_.ignored;
    return;
  }
  // The newest fix reaches the controller with the next step.
  fix_held_ = *fix;
  ++counters_.gps_fixes;
}

MavResult MavlinkDut::HandleGripper(const mavlink::CommandLong& command) {
  const std::optional<host::SetpointMessage> grasped =
      host::WithGripperCommand(command, last_setpoint_);
  if (!grasped) return MavResult::kDenied;
  // The grasp reaches the controller with the next step, as a setpoint would.
  last_setpoint_ = *grasped;
  setpoint_held_ = *grasped;
  return MavResult::kAccepted;
}

void MavlinkDut::HandleCommand(const mavlink::CommandLong& command, MavlinkSender sender) {
  if (!AddressedToUs(command.target_system, command.target_component)) {
    ++counters_.ignored;
    return;
  }
  ++counters_.commands;
  MavResult result = MavResult::kUnsupported;
  if (command.command == host::kMavCmdComponentArmDisarm) {
    const std::optional<std::uint8_t> arm = SmallWholeNumber(command.param1);
    result = arm && *arm <= 1 ? MavResult::kAccepted : MavResult::kDenied;
    if (result == MavResult::kAccepted) arm_commanded_ = *arm == 1;
  } else if (command.command == host::kMavCmdDoSetMode) {
    // param1: MAV_MODE_FLAG bits; param2, param3: PX4's main and sub mode.
    const std::optional<std::uint8_t> flags = SmallWholeNumber(command.param1);
    const std::optional<std::uint8_t> main_mode = SmallWholeNumber(command.param2);
    const std::optional<std::uint8_t> sub_mode = SmallWholeNumber(command.param3);
    result = flags && main_mode && sub_mode ? MavResult::kAccepted : MavResult::kDenied;
    if (result == MavResult::kAccepted) {
      // Arming is the arm command's; a mode change leaves it as it is.
      base_mode_flags_ = static_cast<std::uint8_t>(*flags & ~kModeFlagSafetyArmed);
      // PX4's custom_mode: the main mode in byte 2, the sub mode in byte 3.
      custom_mode_ = (std::uint32_t{*main_mode} << 16) | (std::uint32_t{*sub_mode} << 24);
    }
  } else if (command.command == host::kMavCmdDoGripper) {
    result = HandleGripper(command);
  }
  mavlink::CommandAck ack;
  ack.command = command.command;
  ack.result = static_cast<std::uint8_t>(result);
  ack.target_system = sender.system_id;
  ack.target_component = sender.component_id;
  Send(MavlinkLink::kApi, ack);
}

mavlink::Heartbeat MavlinkDut::MakeHeartbeat() const {
  mavlink::Heartbeat heartbeat;
  heartbeat.custom_mode = custom_mode_;
  heartbeat.type = kMavTypeQuadrotor;
  heartbeat.autopilot = kMavAutopilotPx4;
  heartbeat.base_mode =
      static_cast<std::uint8_t>(base_mode_flags_ | (arm_commanded_ ? kModeFlagSafetyArmed : 0));
  heartbeat.system_status = arm_commanded_ ? kMavStateActive : kMavStateStandby;
  return heartbeat;
}

mavlink::HilActuatorControls MavlinkDut::MakeControls(std::uint64_t time_usec,
                                                      const host::ActuatorMessage& command) const {
  // The motors turn only when both the operator armed and the controller is ready to fly.
  host::ActuatorMessage outputs = command;
  outputs.armed = arm_commanded_ && command.armed;
  return host::ControlsFrom(outputs, range_, time_usec);
}

const char* const kMavlinkDutUsage =
    "   or: dut_emu --mavlink HOST:PORT --api HOST:PORT --config FILE\n"
    "   or: dut_emu --mavlink-serial DEVICE[,baud=N] --config FILE\n"
    "Plays PX4 SITL on the rig's MAVLink simulator link (docs/mavlink.md) with the rig's own\n"
    "flight controller: announces itself with a HEARTBEAT to the API port (UDP), dials the\n"
    "simulator link (TCP, for up to 10 s) and answers each HIL_SENSOR with a\n"
    "HIL_ACTUATOR_CONTROLS. With --mavlink-serial it plays PX4 on a board (HITL): both\n"
    "links on the serial DEVICE, a HEARTBEAT once a second until the first HIL_SENSOR. FILE\n"
    "is the binary DutConfig the runner writes (firmware and sensor period).\n"
    "Exit codes: 0 the simulator closed the link after a step or a signal stopped it, 1 the\n"
    "link, the configuration or the simulator's messages failed, 2 bad usage, 4 the\n"
    "accelerometer and gyro readings repeated 100 times (stale sensors).\n";

namespace {

// "HOST:PORT" or "[V6]:PORT" after `flag`.
rig::Result<std::pair<std::string, std::uint16_t>> ParseHostPort(const std::string& flag,
                                                                 const std::string& text) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) {
    return rig::MakeError(flag + " \"" + text + "\": expected HOST:PORT");
  }
  auto port = rig::ParseNumber<std::uint16_t>(text.substr(colon + 1), flag + " port");
  if (!port || port.value() == 0) return rig::MakeError(flag + " \"" + text + "\": bad port");
  std::string host = text.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  if (host.empty()) return rig::MakeError(flag + " \"" + text + "\": expected HOST:PORT");
  return std::make_pair(host, port.value());
}

}  // namespace

namespace {

// --mavlink-serial DEVICE[,baud=N] --config FILE.
rig::Result<MavlinkDutOptions> ParseSerialArgs(const rig::CliArgs& cli, const std::string& line) {
  const std::string* config = cli.Option("--config");
  if (config == nullptr || config->empty()) return rig::MakeError("--config FILE is required");
  if (cli.Option("--mavlink") != nullptr || cli.Option("--api") != nullptr) {
    return rig::MakeError("--mavlink-serial takes neither --mavlink nor --api");
  }
  MavlinkDutOptions options;
  options.config_path = *config;
  auto port = host::ParseSerialDevice(line, options.baud);
  if (!port) return rig::MakeError("--mavlink-serial \"" + line + "\": " + port.error().message);
  options.serial_device = port.value().device;
  options.baud = port.value().baud;
  return options;
}

}  // namespace

rig::Result<MavlinkDutOptions> ParseMavlinkArgs(const std::vector<std::string>& args) {
  auto parsed = rig::ParseCliArgs(args, {"--mavlink", "--api", "--config", "--mavlink-serial"});
  if (!parsed) return parsed.error();
  const rig::CliArgs& cli = parsed.value();
  if (!cli.positional.empty()) return rig::MakeError("unexpected argument " + cli.positional[0]);
  if (const std::string* line = cli.Option("--mavlink-serial")) return ParseSerialArgs(cli, *line);
  const std::string* simulator = cli.Option("--mavlink");
  const std::string* api = cli.Option("--api");
  const std::string* config = cli.Option("--config");
  if (simulator == nullptr || api == nullptr || config == nullptr) {
    return rig::MakeError("--mavlink, --api and --config are all required");
  }
  MavlinkDutOptions options;
  auto simulator_address = ParseHostPort("--mavlink", *simulator);
  if (!simulator_address) return simulator_address.error();
  auto api_address = ParseHostPort("--api", *api);
  if (!api_address) return api_address.error();
  if (config->empty()) return rig::MakeError("--config: expected a file");
  std::tie(options.simulator_host, options.simulator_port) = simulator_address.value();
  std::tie(options.api_host, options.api_port) = api_address.value();
  options.config_path = *config;
  return options;
}

rig::Result<host::DutSetup> LoadMavlinkDutSetup(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return rig::MakeError("cannot read --config " + path + ": " + std::strerror(errno));
  std::ostringstream bytes;
  bytes << file.rdbuf();
  proto::DutConfig config;
  if (!config.ParseFromString(bytes.str())) {
    return rig::MakeError("--config " + path + " is not a binary DutConfig");
  }
  auto setup = host::FromDutConfig(config);
  if (!setup) return rig::MakeError("--config " + path + ": " + setup.error().message);
  return setup;
}

// Every drop ends the run: a link that carries only the contract's messages has nothing to drop.
std::optional<const char*> DropReason(const mavlink::ParserCounters& counters) {
  if (counters.crc_failures > 0) return "a frame that fails its checksum";
  if (counters.unknown_message_ids > 0) return "a frame of a message id the codec does not know";
  if (counters.bad_lengths > 0) return "a payload longer than its message";
  if (counters.unsupported_incompat_flags > 0) return "a frame with unsupported incompat flags";
  if (counters.v1_frames_skipped > 0) return "a MAVLink v1 frame";
  if (counters.truncated_frames > 0) return "a frame cut off by the end of its stream";
  if (counters.bytes_skipped > 0) return "bytes that are no MAVLink frame";
  return std::nullopt;
}

MavlinkLink LinkOf(std::uint32_t message_id) {
  return message_id == mavlink::CommandLong::kId ||
                 message_id == mavlink::SetPositionTargetLocalNed::kId ||
                 message_id == mavlink::Heartbeat::kId
             ? MavlinkLink::kApi
             : MavlinkLink::kSimulator;
}

namespace {

// How often a wait on a socket looks at the stop request, and how long a failed dial waits before
// the next: both on the OS clock, which only ever bounds waits on sockets.
constexpr int kStopCheckMs = 100;
constexpr long kRedialNs = 5'000'000;

struct Address {
  sockaddr_storage storage{};
  socklen_t length = 0;
};

rig::Result<Address> ResolveDatagramAddress(const std::string& host, std::uint16_t port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  const std::string where = host + ":" + std::to_string(port);
  if (const int status = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found);
      status != 0) {
    return rig::MakeError("cannot resolve --api " + where + ": " + ::gai_strerror(status));
  }
  Address address;
  std::memcpy(&address.storage, found->ai_addr, found->ai_addrlen);
  address.length = found->ai_addrlen;
  ::freeaddrinfo(found);
  return address;
}

bool IsLoopback(const Address& address) {
  if (address.storage.ss_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(&address.storage);
    return (ntohl(v4->sin_addr.s_addr) >> 24) == 127;
  }
  const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&address.storage);
  return IN6_IS_ADDR_LOOPBACK(&v6->sin6_addr);
}

// A non-blocking UDP socket on an ephemeral port: of the loopback interface when the rig's API
// port is on it (the contract's case), of every interface otherwise.
rig::Result<dut_link::OwnedLine> OpenApiSocket(const Address& api) {
  const int family = api.storage.ss_family;
  dut_link::OwnedLine socket(::socket(family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!socket.ok())
    return rig::MakeError(std::string("cannot open a UDP socket: ") + std::strerror(errno));
  Address local;
  local.storage.ss_family = static_cast<sa_family_t>(family);
  const bool loopback = IsLoopback(api);
  if (family == AF_INET) {
    auto* v4 = reinterpret_cast<sockaddr_in*>(&local.storage);
    v4->sin_addr.s_addr = htonl(loopback ? INADDR_LOOPBACK : INADDR_ANY);
    local.length = sizeof(sockaddr_in);
  } else {
    auto* v6 = reinterpret_cast<sockaddr_in6*>(&local.storage);
    v6->sin6_addr = loopback ? in6addr_loopback : in6addr_any;
    local.length = sizeof(sockaddr_in6);
  }
  if (::bind(socket.fd(), reinterpret_cast<const sockaddr*>(&local.storage), local.length) != 0) {
    return rig::MakeError(std::string("cannot bind a UDP socket: ") + std::strerror(errno));
  }
  return socket;
}

// The sockets and the loop around one MavlinkDut.
class MavlinkDutLoop {
 public:
  MavlinkDutLoop(const MavlinkDutOptions& options, const std::atomic<bool>* stop, std::ostream& log,
                 MavlinkDut& dut, dut_link::OwnedLine api_socket, const Address& api)
      : options_(options),
        stop_(stop),
        log_(log),
        dut_(dut),
        api_socket_(std::move(api_socket)),
        api_(api),
        simulator_where_(options.simulator_host + ":" + std::to_string(options.simulator_port)),
        api_where_(options.api_host + ":" + std::to_string(options.api_port)) {}

  int Run();

 private:
  bool Stopping() const { return stop_ != nullptr && stop_->load(); }
  int Stopped() {
    log_ << "dut_emu: stopped by a signal\n";
    return kExitOk;
  }
  int Fail(const std::string& why) {
    log_ << "dut_emu: " << why << "\n";
    return kExitFailed;
  }
  // Dials the simulator link until it answers, the time is up or a stop request comes; nullopt
  // once connected, else the exit code.
  std::optional<int> Dial();
  // Sends what `replies` holds (the API link's first); nullopt to go on, else the exit code.
  std::optional<int> Deliver(const MavlinkReplies& replies);
  bool SendDatagram(std::span<const std::uint8_t> frame);
  bool WriteSimulator(std::span<const std::uint8_t> bytes);
  // Takes every datagram waiting on the API socket; nullopt to go on, else the exit code.
  std::optional<int> DrainApi();
  // Hands the simulator parser's complete frames to the DUT (draining the API link before each
  // HIL_SENSOR); nullopt to go on, else the exit code.
  std::optional<int> TakeSimulatorFrames();
  std::optional<int> CheckDrops(const mavlink::FrameParser& parser, const char* link_name);

  const MavlinkDutOptions& options_;
  const std::atomic<bool>* stop_;
  std::ostream& log_;
  MavlinkDut& dut_;
  dut_link::OwnedLine api_socket_;
  Address api_;
  dut_link::OwnedLine simulator_;
  std::string simulator_where_;
  std::string api_where_;
  mavlink::FrameParser simulator_parser_{mav::FindWireInfo};
  mavlink::FrameParser api_parser_{mav::FindWireInfo};
  // Apart, since the API link is drained while simulator bytes wait to be parsed. A datagram
  // longer than its buffer would be cut: the API buffer holds the largest UDP payload.
  std::array<std::uint8_t, 4096> simulator_buffer_{};
  std::vector<std::uint8_t> api_buffer_ = std::vector<std::uint8_t>(65536);
};

bool MavlinkDutLoop::SendDatagram(std::span<const std::uint8_t> frame) {
  for (;;) {
    const ssize_t sent = ::sendto(api_socket_.fd(), frame.data(), frame.size(), MSG_NOSIGNAL,
                                  reinterpret_cast<const sockaddr*>(&api_.storage), api_.length);
    if (sent >= 0) return true;
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) return false;
    if (Stopping()) return false;
    pollfd out{api_socket_.fd(), POLLOUT, 0};
    ::poll(&out, 1, kStopCheckMs);
  }
}

bool MavlinkDutLoop::WriteSimulator(std::span<const std::uint8_t> bytes) {
  while (!bytes.empty()) {
    const ssize_t sent = ::send(simulator_.fd(), bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (sent > 0) {
      bytes = bytes.subspan(static_cast<std::size_t>(sent));
      continue;
    }
    if (sent < 0 && errno == EINTR) continue;
    if (sent < 0 && errno != EAGAIN && errno != EWOULDBLOCK) return false;
    if (Stopping()) return false;
    pollfd out{simulator_.fd(), POLLOUT, 0};
    ::poll(&out, 1, kStopCheckMs);
  }
  return true;
}

std::optional<int> MavlinkDutLoop::Deliver(const MavlinkReplies& replies) {
  for (std::size_t i = 0; i < replies.api.size(); ++i) {
    if (!SendDatagram(replies.api.frame(i))) {
      if (Stopping()) return Stopped();
      return Fail("cannot send to the API port " + api_where_ + ": " + std::strerror(errno));
    }
  }
  for (std::size_t i = 0; i < replies.simulator.size(); ++i) {
    if (!WriteSimulator(replies.simulator.frame(i))) {
      if (Stopping()) return Stopped();
      return Fail("cannot send to the simulator link " + simulator_where_ + ": " +
                  std::strerror(errno));
    }
  }
  if (replies.end == MavlinkDutEnd::kRunning) return std::nullopt;
  log_ << "dut_emu: " << replies.why << "\n";
  return replies.end == MavlinkDutEnd::kSensorsStale ? kExitSensorsStale : kExitFailed;
}

std::optional<int> MavlinkDutLoop::CheckDrops(const mavlink::FrameParser& parser,
                                              const char* link_name) {
  const std::optional<const char*> reason = DropReason(parser.counters());
  if (!reason) return std::nullopt;
  return Fail(std::string("the ") + link_name + " sent " + *reason +
              ": the codec cannot decode it");
}

std::optional<int> MavlinkDutLoop::DrainApi() {
  for (;;) {
    const ssize_t got = ::recvfrom(api_socket_.fd(), api_buffer_.data(), api_buffer_.size(),
                                   MSG_DONTWAIT, nullptr, nullptr);
    if (got < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) return std::nullopt;
      // EINTR: a signal, looked at by the caller; ECONNREFUSED: an earlier datagram found no
      // listener, which the next heartbeat retries.
      if (errno == EINTR || errno == ECONNREFUSED) continue;
      return Fail("cannot read the API port " + api_where_ + ": " + std::strerror(errno));
    }
    // Each datagram is a stream of its own: a frame cut off at its end is cut off for good.
    std::span<const std::uint8_t> bytes(api_buffer_.data(), static_cast<std::size_t>(got));
    bool ended = false;
    while (!ended) {
      bytes = bytes.subspan(api_parser_.Push(bytes));
      if (bytes.empty()) {
        api_parser_.Finish();
        ended = true;
      }
      while (std::optional<mavlink::Frame> frame = api_parser_.Next()) {
        if (auto done = Deliver(dut_.HandleFrame(*frame, MavlinkLink::kApi))) return done;
      }
      if (auto done = CheckDrops(api_parser_, "API link")) return done;
    }
  }
}

std::optional<int> MavlinkDutLoop::TakeSimulatorFrames() {
  for (;;) {
    std::optional<mavlink::Frame> frame = simulator_parser_.Next();
    if (auto done = CheckDrops(simulator_parser_, "simulator link")) return done;
    if (!frame) return std::nullopt;
    // The contract's commands of a step are in the API socket before its HIL_SENSOR is sent.
    if (frame->message_id == mavlink::HilSensor::kId) {
      if (auto done = DrainApi()) return done;
    }
    if (auto done = Deliver(dut_.HandleFrame(*frame, MavlinkLink::kSimulator))) return done;
  }
}

std::optional<int> MavlinkDutLoop::Dial() {
  // On the OS clock: the dial is a wait on a socket, before the DUT has any time of its own.
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + std::chrono::milliseconds(options_.connect_timeout_ms);
  auto next_announce = start + std::chrono::seconds(1);
  std::string last_error;
  for (;;) {
    if (Stopping()) return Stopped();
    const auto now = std::chrono::steady_clock::now();
    const auto left_ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now).count();
    if (left_ms <= 0) {
      return Fail("no simulator link at --mavlink " + simulator_where_ + " within " +
                  std::to_string(options_.connect_timeout_ms) + " ms (" + last_error + ")");
    }
    dut_link::OwnedLine line =
        dut_link::ConnectTcpLine(options_.simulator_host, options_.simulator_port,
                                 static_cast<int>(std::min<long long>(left_ms, kStopCheckMs)));
    if (line.ok()) {
      simulator_ = std::move(line);
      return std::nullopt;
    }
    last_error = line.error();
    // A heartbeat sent before the rig's API port was open is lost: PX4 repeats it every second.
    if (now >= next_announce) {
      if (auto done = Deliver(dut_.Announce())) return done;
      next_announce += std::chrono::seconds(1);
    }
    const timespec nap{0, kRedialNs};
    ::nanosleep(&nap, nullptr);
  }
}

int MavlinkDutLoop::Run() {
  if (auto done = Deliver(dut_.Announce())) return *done;
  if (auto done = Dial()) return *done;
  for (;;) {
    if (Stopping()) return Stopped();
    // The OS clock bounds this wait only so that a stop request is seen.
    pollfd in{simulator_.fd(), POLLIN, 0};
    if (::poll(&in, 1, kStopCheckMs) <= 0) continue;
    const ssize_t got =
        ::recv(simulator_.fd(), simulator_buffer_.data(), simulator_buffer_.size(), 0);
    if (got < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) continue;
      return Fail("cannot read the simulator link " + simulator_where_ + ": " +
                  std::strerror(errno));
    }
    if (got == 0) {
      simulator_parser_.Finish();
      if (auto done = TakeSimulatorFrames()) return *done;
      const std::uint64_t steps = dut_.counters().sensor_steps;
      if (steps == 0) {
        return Fail("the simulator closed the link " + simulator_where_ +
                    " before its first HIL_SENSOR");
      }
      log_ << "dut_emu: the simulator closed the link after " << steps << " steps";
      if (dut_.counters().ignored > 0) {
        log_ << " (" << dut_.counters().ignored << " messages ignored)";
      }
      log_ << "\n";
      return kExitOk;
    }
    std::span<const std::uint8_t> bytes(simulator_buffer_.data(), static_cast<std::size_t>(got));
    while (!bytes.empty()) {
      bytes = bytes.subspan(simulator_parser_.Push(bytes));
      if (auto done = TakeSimulatorFrames()) return *done;
    }
  }
}

}  // namespace

int RunMavlinkDut(const MavlinkDutOptions& options, const std::atomic<bool>* stop_requested,
                  std::ostream& log) {
  auto setup = LoadMavlinkDutSetup(options.config_path);
  if (!setup) {
    log << "dut_emu: " << setup.error().message << "\n";
    return kExitFailed;
  }
  if (!options.serial_device.empty()) {
    MavlinkDut dut(setup.value().firmware, setup.value().control_period_s);
    return RunMavlinkSerialDut(options, stop_requested, log, dut);
  }
  auto api = ResolveDatagramAddress(options.api_host, options.api_port);
  if (!api) {
    log << "dut_emu: " << api.error().message << "\n";
    return kExitFailed;
  }
  auto api_socket = OpenApiSocket(api.value());
  if (!api_socket) {
    log << "dut_emu: " << api_socket.error().message << "\n";
    return kExitFailed;
  }
  MavlinkDut dut(setup.value().firmware, setup.value().control_period_s);
  MavlinkDutLoop loop(options, stop_requested, log, dut, std::move(api_socket).value(),
                      api.value());
  return loop.Run();
}

}  // namespace hilrig::dut_emu
