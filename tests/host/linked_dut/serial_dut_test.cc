// SerialDut against a scripted DUT on an in-memory line: the peer below speaks the serial-line
// protocol with libprotobuf (what the firmware does with its own codec) and misbehaves on cue. The
// line's wait hook advances a fake clock, so the handshake retries, step retries and the watchdog
// run to exact deadlines with no wall time passing.
#include "host/linked_dut/serial_dut.h"

#include <gtest/gtest.h>
#include <signal.h>

#include <map>
#include <set>

#include "dut_fw/sensor_node.h"
#include "host/dut/firmware_config.h"
#include "host/link/dut_config_codec.h"
#include "host/link/hil_link_codec.h"
#include "host/link/line_link.h"
#include "host/link/memory_byte_stream.h"
#include "rig/clock.h"
#include "rig/emulated_bus.h"

namespace hilrig::host {
namespace {

constexpr double kControlPeriodS = 1e-3;
constexpr std::int64_t kPeriodNs = 1'000'000;

DutFirmware HoverFirmware() {
  return DutFirmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true};
}

// The DUT end of the line, played by the test.
class ScriptedDut {
 public:
  // What it does; the defaults make a well-behaved DUT.
  int hellos_to_ignore = 0;
  std::uint32_t hello_version = kHilLinkProtocolVersion;
  bool refuse_config = false;
  bool silent_from_start = false;
  std::optional<std::uint64_t> silent_from_tick;  // no answer to this tick or later
  std::optional<std::uint64_t> close_at_tick;     // hangs up when asked this tick
  std::function<void()> before_close;             // e.g. the emulator behind the line dies
  std::set<std::uint64_t> lose_first_answer;      // the first answer to these ticks is lost
  std::set<std::uint64_t> flip_first_answer;      // ... arrives with a byte flipped
  std::set<std::uint64_t> garbage_before_answer;  // noise on the line before the answer
  std::uint32_t work_cycles = 0;
  std::uint64_t bridge_bytes_missing = 0;  // the count its answers carry
  std::int64_t answer_delay_ns = 0;        // a slow line: a command leaves this long after its step
  const rig::Clock* clock = nullptr;

  // What it saw.
  int hellos = 0;
  int configs = 0;
  std::optional<proto::DutConfig> config;
  std::vector<proto::SerialStep> steps;  // every step frame, repeats included
  std::vector<std::uint8_t> bridge;      // bytes that arrived on the bridge line
  bool said_bye = false;

  ScriptedDut(MemoryByteStream& line, MemoryByteStream& bridge_line)
      : line_(line), bridge_line_(bridge_line), link_(line) {}

  // Reads everything the runner sent and answers it.
  void Serve() {
    std::array<std::uint8_t, 256> chunk;
    for (StreamRead read = bridge_line_.ReadSome(chunk, 0); read.status == StreamStatus::kData;
         read = bridge_line_.ReadSome(chunk, 0)) {
      bridge.insert(bridge.end(), chunk.begin(), chunk.begin() + read.bytes);
    }
    while (!delayed_.empty() && delayed_.front().first <= clock->NowNs()) {
      Write(delayed_.front().second);
      delayed_.erase(delayed_.begin());
    }
    for (LineReceived received = link_.Receive(0); received.status == LineReceiveStatus::kMessage;
         received = link_.Receive(0)) {
      Answer(received.message);
      if (closed_) return;
    }
  }

  // When the next delayed answer leaves: a wait ends there, as a read does when bytes arrive.
  std::optional<std::int64_t> NextDueNs() const {
    if (delayed_.empty()) return std::nullopt;
    return delayed_.front().first;
  }

 private:
  void Answer(const proto::LinkMessage& message) {
    if (message.has_bye()) said_bye = true;
    if (silent_from_start) return;
    if (message.has_hello()) {
      if (++hellos <= hellos_to_ignore) return;
      proto::LinkMessage hello;
      hello.mutable_hello()->set_role(proto::Hello::DUT);
      hello.mutable_hello()->set_name("scripted dut");
      hello.mutable_hello()->mutable_header()->set_protocol_version(hello_version);
      Write(hello);
    } else if (message.has_config()) {
      ++configs;
      config = message.config();
      proto::LinkMessage answer;
      if (refuse_config) {
        answer.mutable_bye()->set_error(true);
        answer.mutable_bye()->set_reason("tactile nodes missing");
      } else {
        answer.mutable_target_info()->set_board("stm32f405");
        answer.mutable_target_info()->set_core_clock_hz(168'000'000);
        answer.mutable_target_info()->set_flash_used_bytes(40'000);
      }
      Write(answer);
    } else if (message.has_serial_step()) {
      AnswerStep(message.serial_step());
    }
  }

  void AnswerStep(const proto::SerialStep& step) {
    steps.push_back(step);
    const std::uint64_t tick = step.tick();
    if (close_at_tick && tick >= *close_at_tick) {
      if (before_close) before_close();
      line_.Close();
      closed_ = true;
      return;
    }
    if (silent_from_tick && tick >= *silent_from_tick) return;
    const bool first = answered_.insert(tick).second;
    if (first && lose_first_answer.count(tick)) return;
    if (first && garbage_before_answer.count(tick)) {
      const std::array<std::uint8_t, 7> noise = {0x31, 0x00, 0xFE, 0x02, 0x55, 0x13, 0x00};
      ASSERT_TRUE(line_.WriteAll(noise, 0));
    }
    proto::LinkMessage answer;
    proto::SerialCommand* command = answer.mutable_serial_command();
    command->set_answers_tick(tick);
    for (int rotor = 0; rotor < 4; ++rotor) command->add_rotor_thrust_n(float(tick) + rotor);
    for (int axis = 0; axis < 3; ++axis) command->add_estimated_position_m(0.5f * axis);
    for (int axis = 0; axis < 3; ++axis) command->add_external_force_world_n(0);
    command->set_armed(true);
    command->set_work_cycles(work_cycles + std::uint32_t(tick));
    command->mutable_counters()->set_frames_received(steps.size());
    command->mutable_counters()->set_steps_repeated(steps.size() - answered_.size());
    command->mutable_counters()->set_bridge_bytes_missing(bridge_bytes_missing);
    if (first && flip_first_answer.count(tick)) {
      std::string payload;
      answer.SerializeToString(&payload);
      std::vector<std::uint8_t> frame(dut_link::EncodedFrameBytes(payload.size()));
      frame.resize(dut_link::EncodeFrame(
          std::span(reinterpret_cast<const std::uint8_t*>(payload.data()), payload.size()), frame));
      frame[3] ^= 0x04;
      ASSERT_TRUE(line_.WriteAll(frame, 0));
      return;
    }
    if (answer_delay_ns > 0) {
      delayed_.emplace_back(clock->NowNs() + answer_delay_ns, answer);
      return;
    }
    Write(answer);
  }

  void Write(const proto::LinkMessage& message) { ASSERT_TRUE(link_.Send(message, 0)); }

  MemoryByteStream& line_;
  MemoryByteStream& bridge_line_;
  LineLink link_;
  std::set<std::uint64_t> answered_;
  std::vector<std::pair<std::int64_t, proto::LinkMessage>> delayed_;  // due time, answer
  bool closed_ = false;
};

struct Rig {
  rig::FakePacingClock clock;
  rig::EmulatedBus bus;
  std::unique_ptr<rig::CanBus> sensor_node = bus.Connect("hall");
  std::unique_ptr<MemoryByteStream> line_runner, line_dut, bridge_runner, bridge_dut;
  std::unique_ptr<ScriptedDut> dut;
  std::unique_ptr<SerialDut> serial;
  std::optional<ChildProcess> emulator;  // handed over with the lines, when set before Start
  std::unique_ptr<rig::CanBus> dut_can;  // the DUT's own CAN port, when set before Start
  double byte_time_s = 0;                // the line's, as the opener would know it
  std::int64_t waited_ns = 0;

  explicit Rig(const std::function<void(ScriptedDut&)>& script = {},
               DutPacing pacing = DutPacing::kLockstep) {
    std::tie(line_runner, line_dut) = MakeMemoryStreamPair("line");
    std::tie(bridge_runner, bridge_dut) = MakeMemoryStreamPair("bridge");
    dut = std::make_unique<ScriptedDut>(*line_dut, *bridge_dut);
    dut->clock = &clock;
    if (script) script(*dut);
    line_runner->set_idle_hook([this] { dut->Serve(); });
    line_runner->set_wait_hook([this](int timeout_ms) {
      std::int64_t wait_ns = std::int64_t{timeout_ms} * 1'000'000;
      if (const std::optional<std::int64_t> due_ns = dut->NextDueNs()) {
        wait_ns = std::clamp<std::int64_t>(*due_ns - clock.NowNs(), 0, wait_ns);
      }
      clock.AdvanceNs(wait_ns);
      waited_ns += wait_ns;
    });
    SerialDutOptions options;
    options.clock = &clock;
    options.answer_timeout_s = 0.5;
    options.start_timeout_s = 2.0;
    options.pacing = pacing;
    auto opener = [this](double) -> rig::Result<SerialLines> {
      SerialLines lines;
      lines.link = std::move(line_runner);
      lines.bridge = std::move(bridge_runner);
      lines.description = "an in-memory line";
      lines.emulator = std::move(emulator);
      lines.byte_time_s = byte_time_s;
      if (dut_can) {
        lines.can = std::move(dut_can);
        lines.can_uri = "socketcan:can0";
      }
      return lines;
    };
    serial = std::make_unique<SerialDut>(HoverFirmware(), bus.Connect("dut"), kControlPeriodS,
                                         opener, options);
  }

  double Metric(const std::string& name) const { return MetricNamed(name).value; }
  rig::Unit UnitOf(const std::string& name) const { return MetricNamed(name).unit; }
  rig::Metric MetricNamed(const std::string& name) const {
    for (const rig::Metric& metric : serial->link_metrics()) {
      if (metric.name == name) return metric;
    }
    ADD_FAILURE() << "no metric " << name;
    return {name, -1, rig::Unit::kCount};
  }
};

// A step retry must come before the watchdog gives up, or a lost frame ends the run.
TEST(SerialDutTest, OptionsRefuseARetryNoShorterThanTheWatchdog) {
  SerialDutOptions options;
  EXPECT_TRUE(ValidateSerialDutOptions(options).ok());
  options.step_retry_s = options.answer_timeout_s;
  const auto refused = ValidateSerialDutOptions(options);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("must be shorter than the answer timeout"),
            std::string::npos)
      << refused.error().message;
}

TEST(SerialDutTest, RepeatsTheHelloUntilTheDutAnswersThenKeepsItsTarget) {
  Rig rig([](ScriptedDut& dut) { dut.hellos_to_ignore = 2; });
  ASSERT_TRUE(rig.serial->Start()) << rig.serial->description();
  EXPECT_EQ(rig.dut->hellos, 3);
  EXPECT_EQ(rig.dut->configs, 1);
  // Two ignored hellos cost two hello intervals of 100 ms.
  EXPECT_GE(rig.clock.NowNs(), 200'000'000);
  EXPECT_LT(rig.clock.NowNs(), 300'000'000);
  ASSERT_TRUE(rig.dut->config);
  auto setup = FromDutConfig(*rig.dut->config);
  ASSERT_TRUE(setup) << setup.error().message;
  EXPECT_EQ(setup.value().control_period_s, kControlPeriodS);
  ASSERT_TRUE(rig.serial->target());
  EXPECT_EQ(rig.serial->target()->board, "stm32f405");
  EXPECT_EQ(rig.serial->target()->flash_used_bytes, 40'000u);
  EXPECT_NE(rig.serial->description().find("stm32f405"), std::string::npos);
  EXPECT_EQ(rig.Metric("line_hellos_sent"), 3);
  EXPECT_EQ(rig.Metric("target_core_clock_hz"), 168e6);
  // Each figure carries the unit it was measured in, not "count" for all.
  EXPECT_EQ(rig.UnitOf("line_hellos_sent"), rig::Unit::kCount);
  EXPECT_EQ(rig.UnitOf("target_core_clock_hz"), rig::Unit::kHertz);
  EXPECT_EQ(rig.UnitOf("target_flash_used_bytes"), rig::Unit::kBytes);
  rig.serial->Stop();
  rig.dut->Serve();
  EXPECT_TRUE(rig.dut->said_bye);
}

TEST(SerialDutTest, RefusesADutOfAnotherProtocolVersion) {
  Rig rig([](ScriptedDut& dut) { dut.hello_version = kHilLinkProtocolVersion + 1; });
  auto started = rig.serial->Start();
  ASSERT_FALSE(started);
  EXPECT_EQ(LinkErrorKindOf(started.error()), LinkErrorKind::kBadVersion);
  EXPECT_NE(started.error().message.find("version " + std::to_string(kHilLinkProtocolVersion + 1)),
            std::string::npos)
      << started.error().message;
}

TEST(SerialDutTest, NamesTheReasonADutRefusesTheConfiguration) {
  Rig rig([](ScriptedDut& dut) { dut.refuse_config = true; });
  auto started = rig.serial->Start();
  ASSERT_FALSE(started);
  EXPECT_NE(started.error().message.find("refused the firmware configuration: tactile nodes"),
            std::string::npos)
      << started.error().message;
}

TEST(SerialDutTest, GivesUpOnASilentDutAtTheStartTimeout) {
  Rig rig([](ScriptedDut& dut) { dut.silent_from_start = true; });
  auto started = rig.serial->Start();
  ASSERT_FALSE(started);
  EXPECT_EQ(started.error().code, rig::ErrorCode::kTimeout);
  EXPECT_NE(started.error().message.find("did not answer the hello within 2 s"), std::string::npos)
      << started.error().message;
  EXPECT_GE(rig.clock.NowNs(), 2'000'000'000);
  EXPECT_LT(rig.clock.NowNs(), 2'100'000'000);
  EXPECT_EQ(rig.Metric("line_hellos_sent"), 20);
}

SetpointMessage Setpoint(double x, double yaw) {
  SetpointMessage setpoint;
  setpoint.position_m = {x, 2, 3};
  setpoint.yaw_rad = yaw;
  setpoint.grasp_force_n = 1.5;
  return setpoint;
}

TEST(SerialDutTest, SendsTheTicksInputsInOrderAndOnlyTheSetpointFieldsThatChanged) {
  Rig rig;
  ASSERT_TRUE(rig.serial->Start());
  ImuMessage imu;
  imu.stamp.time_ns = 5 * kPeriodNs - 250'000;
  imu.gyro_rad_s = {0.1, 0.2, 0.3};
  imu.accel_m_s2 = {0, 0, 9.81};
  VioMessage vio;
  vio.capture_time_ns = 5 * kPeriodNs - 20'000'000;
  vio.position_m = {1, 2, 3};
  rig.serial->Send(imu);
  rig.serial->Send(Setpoint(1, 0));
  rig.serial->Send(vio);
  rig.serial->Send(Setpoint(1, 0));    // unchanged: an empty setpoint keeps the order
  rig.serial->Send(Setpoint(1, 0.5));  // the yaw only
  auto command = rig.serial->Step(5, 5 * kPeriodNs + 1'000);
  ASSERT_TRUE(command) << command.error().message;
  EXPECT_EQ(command.value().answers_sequence, 5u);
  EXPECT_EQ(command.value().rotor_thrust_n[3], 8.0);
  EXPECT_EQ(command.value().estimated_position_m.y(), 0.5);

  ASSERT_EQ(rig.dut->steps.size(), 1u);
  const proto::SerialStep& step = rig.dut->steps[0];
  EXPECT_EQ(step.tick(), 5u);
  EXPECT_EQ(step.now_offset_ns(), 1'000);
  ASSERT_EQ(step.inputs_size(), 5);
  ASSERT_TRUE(step.inputs(0).has_imu());
  EXPECT_EQ(step.inputs(0).imu().time_offset_ns(), -251'000);
  EXPECT_EQ(step.inputs(0).imu().gyro_accel_size(), 6);
  EXPECT_FLOAT_EQ(step.inputs(0).imu().gyro_accel(5), 9.81f);
  ASSERT_TRUE(step.inputs(1).has_setpoint());
  EXPECT_EQ(step.inputs(1).setpoint().position_m_size(), 3);
  EXPECT_TRUE(step.inputs(1).setpoint().has_grasp_force_n());
  ASSERT_TRUE(step.inputs(2).has_vio());
  EXPECT_EQ(step.inputs(2).vio().capture_offset_ns(), -20'001'000);
  EXPECT_EQ(step.inputs(2).vio().orientation_wxyz(0), 1.0f);
  ASSERT_TRUE(step.inputs(3).has_setpoint());
  EXPECT_EQ(step.inputs(3).setpoint().ByteSizeLong(), 0u);
  ASSERT_TRUE(step.inputs(4).has_setpoint());
  EXPECT_TRUE(step.inputs(4).setpoint().has_yaw_rad());
  EXPECT_FLOAT_EQ(step.inputs(4).setpoint().yaw_rad(), 0.5f);
  EXPECT_EQ(step.inputs(4).setpoint().position_m_size(), 0);
  EXPECT_FALSE(step.inputs(4).setpoint().has_grasp_force_n());
  EXPECT_EQ(rig.serial->counters().imu_messages, 1u);

  // A tick on the grid carries no offset, and a tick without inputs none.
  ASSERT_TRUE(rig.serial->Step(6, 6 * kPeriodNs));
  EXPECT_EQ(rig.dut->steps[1].now_offset_ns(), 0);
  EXPECT_EQ(rig.dut->steps[1].inputs_size(), 0);
}

TEST(SerialDutTest, RecoversALostAnswerByRepeatingTheStep) {
  Rig rig([](ScriptedDut& dut) { dut.lose_first_answer = {2}; });
  ASSERT_TRUE(rig.serial->Start());
  ASSERT_TRUE(rig.serial->Step(1, kPeriodNs));
  rig.serial->Send(Setpoint(4, 0));
  auto command = rig.serial->Step(2, 2 * kPeriodNs);
  ASSERT_TRUE(command) << command.error().message;
  EXPECT_EQ(command.value().answers_sequence, 2u);
  ASSERT_EQ(rig.dut->steps.size(), 3u);
  // The repeat is the same step, inputs and all.
  EXPECT_EQ(rig.dut->steps[2].SerializeAsString(), rig.dut->steps[1].SerializeAsString());
  EXPECT_EQ(rig.dut->steps[2].inputs_size(), 1);
  EXPECT_EQ(rig.Metric("line_step_retries"), 1);
  EXPECT_EQ(rig.Metric("dut_steps_repeated"), 1);
  EXPECT_GE(rig.waited_ns, 50'000'000);  // one retry timeout
}

// At 1 ms a byte, a step without inputs (4 bytes, 8 on the line) waits 2 x 8 ms on top of the 50 ms
// retry timeout: an answer after 60 ms is waited for, one after 80 ms costs one repeat.
TEST(SerialDutTest, WaitsLongerBeforeRepeatingOnASlowLine) {
  for (const auto& [delay_ns, retries] :
       {std::pair{std::int64_t{60'000'000}, 0}, std::pair{std::int64_t{80'000'000}, 1}}) {
    Rig rig([delay_ns](ScriptedDut& dut) { dut.answer_delay_ns = delay_ns; });
    rig.byte_time_s = 1e-3;
    ASSERT_TRUE(rig.serial->Start());
    ASSERT_TRUE(rig.serial->Step(1, kPeriodNs));
    EXPECT_EQ(rig.Metric("line_step_retries"), retries) << delay_ns;
  }
}

TEST(SerialDutTest, CountsGarbageAndAFlippedAnswerAndRidesThrough) {
  Rig rig([](ScriptedDut& dut) {
    dut.garbage_before_answer = {1, 3};
    dut.flip_first_answer = {2};
  });
  ASSERT_TRUE(rig.serial->Start());
  for (std::uint64_t tick = 1; tick <= 4; ++tick) {
    auto command = rig.serial->Step(tick, std::int64_t(tick) * kPeriodNs);
    ASSERT_TRUE(command) << command.error().message;
    EXPECT_EQ(command.value().answers_sequence, tick);
  }
  EXPECT_GE(rig.Metric("line_bad_checksum") + rig.Metric("line_malformed"), 3);
  EXPECT_EQ(rig.Metric("line_step_retries"), 1);  // only the flipped answer cost a retry
  EXPECT_EQ(rig.Metric("line_commands_received"), 4);
}

TEST(SerialDutTest, EndsARunWithANamedTimeoutWhenTheDutFallsSilent) {
  Rig rig([](ScriptedDut& dut) { dut.silent_from_tick = 3; });
  ASSERT_TRUE(rig.serial->Start());
  ASSERT_TRUE(rig.serial->Step(1, kPeriodNs));
  ASSERT_TRUE(rig.serial->Step(2, 2 * kPeriodNs));
  const std::int64_t before_ns = rig.clock.NowNs();
  auto command = rig.serial->Step(3, 3 * kPeriodNs);
  ASSERT_FALSE(command);
  EXPECT_EQ(command.error().code, rig::ErrorCode::kTimeout);
  EXPECT_NE(command.error().message.find("did not answer tick 3 within 0.5 s"), std::string::npos)
      << command.error().message;
  EXPECT_GE(rig.clock.NowNs() - before_ns, 500'000'000);
  EXPECT_LT(rig.clock.NowNs() - before_ns, 600'000'000);
  EXPECT_EQ(rig.Metric("line_watchdog_timeouts"), 1);
  EXPECT_GE(rig.dut->steps.size(), 10u);  // it kept asking meanwhile
  // The failure sticks.
  auto again = rig.serial->Step(4, 4 * kPeriodNs);
  ASSERT_FALSE(again);
  EXPECT_EQ(again.error().message, command.error().message);
}

TEST(SerialDutTest, NamesALineThePeerClosed) {
  Rig rig([](ScriptedDut& dut) { dut.close_at_tick = 2; });
  ASSERT_TRUE(rig.serial->Start());
  ASSERT_TRUE(rig.serial->Step(1, kPeriodNs));
  auto command = rig.serial->Step(2, 2 * kPeriodNs);
  ASSERT_FALSE(command);
  EXPECT_EQ(command.error().code, rig::ErrorCode::kLinkClosed);
  EXPECT_NE(command.error().message.find("serial line closed"), std::string::npos)
      << command.error().message;
}

TEST(SerialDutTest, NamesTheEmulatorThatDiedAndReapsIt) {
  Rig rig;
  auto sleep_path = FindInPath("sleep");
  ASSERT_TRUE(sleep_path) << sleep_path.error().message;
  auto child = ChildProcess::Spawn({sleep_path.value(), "1000"});
  ASSERT_TRUE(child) << child.error().message;
  const pid_t pid = child.value().pid();
  rig.emulator = std::move(child).value();
  rig.dut->close_at_tick = 2;
  rig.dut->before_close = [pid] { ::kill(pid, SIGKILL); };
  ASSERT_TRUE(rig.serial->Start());
  ASSERT_TRUE(rig.serial->Step(1, kPeriodNs));
  auto command = rig.serial->Step(2, 2 * kPeriodNs);
  ASSERT_FALSE(command);
  EXPECT_EQ(command.error().message, "the dut's emulator killed by signal 9");
  rig.serial->Stop();
  EXPECT_NE(::kill(pid, 0), 0);  // reaped: the pid is gone
}

TEST(SerialDutTest, WritesTheSensorFramesOnTheBridgeAndAnnouncesTheirBytes) {
  Rig rig;
  ASSERT_TRUE(rig.serial->Start());
  const std::array<std::uint8_t, 8> sample = {1, 2, 3, 4, 5, 6, 7, 8};
  const std::array<std::uint8_t, 2> status = {0x10, 0x00};
  ASSERT_TRUE(rig.sensor_node->Send(rig::CanFrame::Classic(0x101, sample), 100));
  ASSERT_TRUE(rig.sensor_node->Send(rig::CanFrame::Classic(0x187, status), 200));
  ASSERT_TRUE(rig.serial->Step(1, kPeriodNs));

  std::vector<std::uint8_t> expected;
  std::array<std::uint8_t, dut_fw::kUartMaxFrameBytes> encoded;
  for (const auto& [id, payload] :
       {std::pair{std::uint16_t{0x101}, std::span<const std::uint8_t>(sample)},
        {std::uint16_t{0x187}, std::span<const std::uint8_t>(status)}}) {
    dut_fw::NodeFrame frame{id, std::uint8_t(payload.size()), {}};
    std::copy(payload.begin(), payload.end(), frame.data.begin());
    const std::size_t size = dut_fw::EncodeUartFrame(frame, encoded);
    expected.insert(expected.end(), encoded.begin(), encoded.begin() + size);
  }
  EXPECT_EQ(rig.dut->bridge, expected);
  ASSERT_EQ(rig.dut->steps.size(), 1u);
  EXPECT_EQ(rig.dut->steps[0].bridge_bytes(), expected.size());
  EXPECT_EQ(rig.serial->counters().can_frames_received, 2u);
  EXPECT_EQ(rig.Metric("bridge_frames_sent"), 2);
  // Nothing new on the bus: nothing on the bridge, nothing announced.
  ASSERT_TRUE(rig.serial->Step(2, 2 * kPeriodNs));
  EXPECT_EQ(rig.dut->steps[1].bridge_bytes(), 0u);
}

TEST(SerialDutTest, ABoardWithItsOwnCanPortGetsTheFramesThereUnannounced) {
  rig::EmulatedBus board_bus;  // outlives the rig, whose dut holds an endpoint of it
  Rig rig;
  rig.dut_can = board_bus.Connect("runner");
  const std::unique_ptr<rig::CanBus> board = board_bus.Connect("board");
  ASSERT_TRUE(rig.serial->Start());
  const std::array<std::uint8_t, 8> sample = {1, 2, 3, 4, 5, 6, 7, 8};
  ASSERT_TRUE(rig.sensor_node->Send(rig::CanFrame::Classic(0x101, sample), 100));
  ASSERT_TRUE(rig.serial->Step(1, kPeriodNs));

  std::vector<rig::TimedCanFrame> received;
  board->Receive(kPeriodNs, received);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].frame, rig::CanFrame::Classic(0x101, sample));
  EXPECT_TRUE(rig.dut->bridge.empty());
  ASSERT_EQ(rig.dut->steps.size(), 1u);
  EXPECT_EQ(rig.dut->steps[0].bridge_bytes(), 0u);  // nothing for the board to wait for
  EXPECT_EQ(rig.Metric("link_can_frames_forwarded"), 1);
  EXPECT_NE(rig.serial->description().find("CAN frames over socketcan:can0"), std::string::npos)
      << rig.serial->description();
}

TEST(SerialDutTest, ReportsTheWorkPerStepTheDutMeasured) {
  Rig rig([](ScriptedDut& dut) { dut.work_cycles = 1000; });
  ASSERT_TRUE(rig.serial->Start());
  for (std::uint64_t tick = 1; tick <= 100; ++tick) {
    ASSERT_TRUE(rig.serial->Step(tick, std::int64_t(tick) * kPeriodNs));
  }
  const std::optional<TargetSummary> target = rig.serial->target();
  ASSERT_TRUE(target);
  EXPECT_EQ(target->steps_measured, 100u);
  EXPECT_EQ(target->work_p50_cycles, 1050u);
  EXPECT_EQ(target->work_p99_cycles, 1099u);
  EXPECT_EQ(target->work_max_cycles, 1100u);
  EXPECT_EQ(rig.Metric("target_work_p99_cycles"), 1099);
  EXPECT_EQ(rig.Metric("dut_line_frames_received"), 100);
}

TEST(SerialDutTest, CountsTheSensorBytesTheBoardSteppedWithout) {
  Rig rig([](ScriptedDut& dut) { dut.bridge_bytes_missing = 38; });
  ASSERT_TRUE(rig.serial->Start());
  EXPECT_EQ(rig.serial->counters().sensor_bytes_missing, 0u);
  ASSERT_TRUE(rig.serial->Step(1, kPeriodNs));
  EXPECT_EQ(rig.serial->counters().sensor_bytes_missing, 38u);
  EXPECT_EQ(rig.Metric("dut_bridge_bytes_missing"), 38);
}

TEST(SerialDutTest, AnswersRealTimeRequestsByPollAndTimesOutTheOldest) {
  Rig rig([](ScriptedDut& dut) { dut.silent_from_tick = 3; }, DutPacing::kRealtime);
  ASSERT_TRUE(rig.serial->Start());
  rig.serial->RequestStep(1, kPeriodNs);
  rig.serial->RequestStep(2, 2 * kPeriodNs);
  auto polled = rig.serial->PollCommand();
  ASSERT_TRUE(polled) << polled.error().message;
  ASSERT_TRUE(polled.value());
  EXPECT_EQ(polled.value()->answers_sequence, 2u);  // the newest of the two answers
  ASSERT_EQ(rig.dut->steps.size(), 2u);
  EXPECT_TRUE(rig.dut->steps[0].realtime());
  // A board measures no latency of its own: the runner times each request to its answer.
  const std::vector<StreamLatency> latencies = rig.serial->response_latencies();
  ASSERT_EQ(latencies.size(), 1u);
  EXPECT_EQ(latencies[0].stream, "command");
  EXPECT_EQ(latencies[0].latency.count, 2u);
  rig.serial->RequestStep(3, 3 * kPeriodNs);
  polled = rig.serial->PollCommand();
  ASSERT_TRUE(polled);
  EXPECT_FALSE(polled.value());
  rig.clock.AdvanceNs(600'000'000);
  polled = rig.serial->PollCommand();
  ASSERT_FALSE(polled);
  EXPECT_EQ(polled.error().code, rig::ErrorCode::kTimeout);
  EXPECT_NE(polled.error().message.find("tick 3"), std::string::npos) << polled.error().message;
}

}  // namespace
}  // namespace hilrig::host
