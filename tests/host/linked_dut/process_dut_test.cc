// Integration tests with a real dut_emu process on loopback sockets. Waits are bounded by the
// watchdog; no test sleeps.
#include "host/linked_dut/process_dut.h"

#include <gtest/gtest.h>
#include <signal.h>

#include <cerrno>
#include <cstdlib>
#include <string>
#include <vector>

#include "host/dut/firmware_config.h"
#include "host/dut/in_process_dut.h"
#include "host/link/hil_link_codec.h"
#include "host/link/link_token.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"
#include "rig/clock.h"
#include "rig/emulated_bus.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

constexpr double kControlPeriodS = 1e-3;

ProcessDutOptions TestOptions(std::vector<std::string> extra_args = {}) {
  ProcessDutOptions options;
  options.dut_emu_path = ::hilrig::test_support::BinDir() + "/dut_emu";
  options.extra_args = std::move(extra_args);
  return options;
}

DutFirmware HoverFirmware() {
  return DutFirmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true};
}

// The same hover inputs into any DUT; returns the command of the last tick.
rig::Result<ActuatorMessage> Hover(DutPort& dut, int ticks) {
  const QuadrotorParams vehicle;
  dut.Send(VioMessage{{0, 0}, 0, Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity()});
  dut.Send(SetpointMessage{
      {0, 0}, Eigen::Vector3d(0, 0, 1.2), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.3});
  rig::Result<ActuatorMessage> command = rig::MakeError("no tick");
  for (int i = 1; i <= ticks; ++i) {
    const std::int64_t now_ns = i * 1'000'000;
    dut.Send(ImuMessage{{static_cast<std::uint64_t>(i - 1), now_ns},
                        Eigen::Vector3d(0.01, -0.02, 0.003),
                        Eigen::Vector3d(0.1, 0, vehicle.gravity_m_s2)});
    command = dut.Step(static_cast<std::uint64_t>(i), now_ns);
    if (!command) return command;
  }
  return command;
}

class ProcessDutTest : public ::testing::Test {
 protected:
  std::unique_ptr<ProcessDut> Start(std::vector<std::string> extra_args = {},
                                    double answer_timeout_s = 1.0) {
    ProcessDutOptions options = TestOptions(std::move(extra_args));
    options.answer_timeout_s = answer_timeout_s;
    auto dut = ProcessDut::Launch(HoverFirmware(), bus_.Connect("dut"), kControlPeriodS, options);
    EXPECT_TRUE(dut.ok()) << (dut.ok() ? "" : dut.error().message);
    return dut.ok() ? std::move(dut).value() : nullptr;
  }

  rig::EmulatedBus bus_;
};

TEST_F(ProcessDutTest, AnswersBitForBitLikeTheInProcessDut) {
  rig::EmulatedBus reference_bus;
  InProcessDut reference(HoverFirmware(), reference_bus.Connect("dut"), kControlPeriodS);
  const ActuatorMessage expected = Hover(reference, 300).value();
  auto dut = Start();
  ASSERT_NE(dut, nullptr);
  const ActuatorMessage actual = Hover(*dut, 300).value();
  ASSERT_TRUE(expected.armed);
  EXPECT_EQ(actual.answers_sequence, 300u);
  EXPECT_TRUE(actual.armed);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(actual.rotor_thrust_n[i], expected.rotor_thrust_n[i]);
  EXPECT_EQ(actual.estimated_position_m, expected.estimated_position_m);
  EXPECT_EQ(actual.servo_angle_rad, expected.servo_angle_rad);
}

TEST_F(ProcessDutTest, KilledProcessEndsTheStepWithItsSignal) {
  auto dut = Start({}, 30.0);  // a watchdog this long would fail the test's own timeout
  ASSERT_NE(dut, nullptr);
  ASSERT_TRUE(Hover(*dut, 5).ok());
  ASSERT_EQ(::kill(dut->pid(), SIGKILL), 0);
  const auto command = dut->Step(6, 6'000'000);
  ASSERT_FALSE(command.ok());
  EXPECT_EQ(command.error().message, "dut process killed by signal 9");
}

TEST_F(ProcessDutTest, ProcessThatExitsIsReportedWithItsStatus) {
  auto dut = Start({"--test-exit-at-tick", "4"});
  ASSERT_NE(dut, nullptr);
  const auto command = Hover(*dut, 10);
  ASSERT_FALSE(command.ok());
  EXPECT_EQ(command.error().message, "dut process exited with status 3");
}

TEST_F(ProcessDutTest, SilentDutTripsTheWatchdog) {
  auto dut = Start({"--test-silent-at-tick", "3"}, 0.2);
  ASSERT_NE(dut, nullptr);
  const auto command = Hover(*dut, 10);
  ASSERT_FALSE(command.ok());
  EXPECT_EQ(command.error().message, "the dut did not answer tick 3 within 0.2 s");
  EXPECT_EQ(command.error().code, rig::ErrorCode::kTimeout);
  bool counted = false;
  for (const auto& [name, value, unit] : dut->link_metrics()) {
    if (name == "link_watchdog_timeouts") counted = value == 1.0;
  }
  EXPECT_TRUE(counted);
}

TEST_F(ProcessDutTest, GarbageAnswerIsRejectedAndCounted) {
  auto dut = Start({"--test-garbage-at-tick", "3"});
  ASSERT_NE(dut, nullptr);
  const auto command = Hover(*dut, 10);
  ASSERT_FALSE(command.ok());
  EXPECT_NE(command.error().message.find("dut sent a bad message (malformed"), std::string::npos)
      << command.error().message;
  EXPECT_EQ(command.error().code, rig::ErrorCode::kLinkProtocol);
  EXPECT_EQ(LinkErrorKindOf(command.error()), LinkErrorKind::kMalformed);
  double malformed = -1;
  for (const auto& [name, value, unit] : dut->link_metrics()) {
    if (name == "link_rx_malformed") malformed = value;
  }
  EXPECT_EQ(malformed, 1.0);
}

TEST_F(ProcessDutTest, FailureSticksForLaterSteps) {
  auto dut = Start({"--test-exit-at-tick", "2"});
  ASSERT_NE(dut, nullptr);
  ASSERT_FALSE(Hover(*dut, 3).ok());
  const auto again = dut->Step(4, 4'000'000);
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.error().message, "dut process exited with status 3");
}

TEST_F(ProcessDutTest, DestructorEndsAndReapsTheProcess) {
  auto dut = Start();
  ASSERT_NE(dut, nullptr);
  const pid_t pid = dut->pid();
  dut.reset();
  errno = 0;
  EXPECT_EQ(::kill(pid, 0), -1);  // reaped: no such process any more
  EXPECT_EQ(errno, ESRCH);
}

// The shared-memory link is the default; the child reaches it by an inherited descriptor alone,
// so it needs no token.
TEST_F(ProcessDutTest, SharedMemoryLinkNeedsNoToken) {
  auto dut = Start();
  ASSERT_NE(dut, nullptr);
  const std::string proc = "/proc/" + std::to_string(dut->pid());
  EXPECT_EQ(ReadFile(proc + "/environ").find(kLinkTokenEnvironment), std::string::npos);
  EXPECT_NE(ReadFile(proc + "/cmdline").find(std::string("--link-shm") + '\0'), std::string::npos);
  EXPECT_NE(dut->description().find("shared-memory"), std::string::npos);
}

// `ps` shows every process's command line to every user; the token must not be there.
TEST_F(ProcessDutTest, LinkTokenTravelsInTheChildsEnvironmentNotItsCommandLine) {
  ProcessDutOptions options = TestOptions();
  options.transport = DutLinkTransport::kTcp;
  auto launched =
      ProcessDut::Launch(HoverFirmware(), bus_.Connect("dut"), kControlPeriodS, options);
  ASSERT_TRUE(launched.ok()) << launched.error().message;
  std::unique_ptr<ProcessDut> dut = std::move(launched).value();
  const std::string proc = "/proc/" + std::to_string(dut->pid());
  const std::string environment = ReadFile(proc + "/environ");
  const std::string variable = std::string(kLinkTokenEnvironment) + "=";
  const std::size_t at = environment.find(variable);
  ASSERT_NE(at, std::string::npos);
  const std::string token = environment.substr(at + variable.size(), 32);
  EXPECT_TRUE(ParseLinkToken(token).ok());
  const std::string command_line = ReadFile(proc + "/cmdline");
  ASSERT_FALSE(command_line.empty());
  EXPECT_EQ(command_line.find(token), std::string::npos);
}

TEST_F(ProcessDutTest, MissingExecutableIsAClearStartError) {
  ProcessDutOptions options = TestOptions();
  options.dut_emu_path = "/nonexistent/dut_emu";
  const auto dut =
      ProcessDut::Launch(HoverFirmware(), bus_.Connect("dut"), kControlPeriodS, options);
  ASSERT_FALSE(dut.ok());
  EXPECT_NE(dut.error().message.find("no dut_emu executable at /nonexistent/dut_emu"),
            std::string::npos);
}

// The argv a running process was started with, from /proc.
std::vector<std::string> CommandLineOf(pid_t pid) {
  const std::string raw = ReadFile("/proc/" + std::to_string(pid) + "/cmdline");
  std::vector<std::string> argv;
  std::size_t start = 0;
  for (std::size_t end = raw.find('\0'); end != std::string::npos; end = raw.find('\0', start)) {
    argv.push_back(raw.substr(start, end - start));
    start = end + 1;
  }
  return argv;
}

// `--dut exec:`: a program of the user's in dut_emu's place. dut_emu itself stands in for one
// here: it speaks the link, and takes an argument of its own before the link's.
TEST_F(ProcessDutTest, AProgramTakesDutEmusPlaceWithItsOwnArgumentsFirst) {
  ProcessDutOptions options;
  options.program = ::hilrig::test_support::BinDir() + "/dut_emu";
  options.program_args = {"--frame-timeout-ms", "2000"};
  auto dut = ProcessDut::Launch(HoverFirmware(), bus_.Connect("dut"), kControlPeriodS, options);
  ASSERT_TRUE(dut.ok()) << dut.error().message;
  EXPECT_TRUE(Hover(*dut.value(), 50).ok());
  const std::string description = dut.value()->description();
  EXPECT_NE(description.find("the program " + options.program + " (pid "), std::string::npos)
      << description;
  const std::size_t pid_at = description.find("(pid ") + 5;
  const std::vector<std::string> argv = CommandLineOf(std::stoi(description.substr(pid_at)));
  ASSERT_GE(argv.size(), 5u);
  EXPECT_EQ(argv[0], options.program);
  EXPECT_EQ(argv[1], "--frame-timeout-ms");
  EXPECT_EQ(argv[2], "2000");
  EXPECT_EQ(argv[3], "--link-shm");
}

TEST_F(ProcessDutTest, AProgramNamedWithoutAPathIsLookedUpInPath) {
  const char* saved = std::getenv("PATH");
  const std::string old_path = saved != nullptr ? saved : "";
  ::setenv("PATH", ("/nonexistent:" + ::hilrig::test_support::BinDir()).c_str(), 1);
  ProcessDutOptions options;
  options.program = "dut_emu";
  auto dut = ProcessDut::Launch(HoverFirmware(), bus_.Connect("dut"), kControlPeriodS, options);
  options.program = "no_such_dut_program";
  auto missing =
      ProcessDut::Launch(HoverFirmware(), bus_.Connect("dut2"), kControlPeriodS, options);
  ::setenv("PATH", old_path.c_str(), 1);
  ASSERT_TRUE(dut.ok()) << dut.error().message;
  EXPECT_TRUE(Hover(*dut.value(), 10).ok());
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "no program \"no_such_dut_program\" in PATH");
}

TEST_F(ProcessDutTest, AProgramThatIsNotThereOrSaysNothingIsAClearStartError) {
  ProcessDutOptions options;
  options.program = "/nonexistent/my_dut";
  const auto missing =
      ProcessDut::Launch(HoverFirmware(), bus_.Connect("dut"), kControlPeriodS, options);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "no executable program at /nonexistent/my_dut");
  options.program = "/bin/true";  // exits at once, without a hello
  const auto silent =
      ProcessDut::Launch(HoverFirmware(), bus_.Connect("dut2"), kControlPeriodS, options);
  ASSERT_FALSE(silent.ok());
  EXPECT_NE(silent.error().message.find("dut process exited with status 0 before it could say "
                                        "hello"),
            std::string::npos)
      << silent.error().message;
}

TEST(ProcessDutOptionsTest, RefusesBadTimeouts) {
  for (double timeout_s : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()}) {
    ProcessDutOptions options;
    options.answer_timeout_s = timeout_s;
    EXPECT_FALSE(ValidateProcessDutOptions(options).ok()) << timeout_s;
  }
}

TEST(ProcessDutOptionsTest, ListenAddressIsForTheTcpLinkOnly) {
  ProcessDutOptions options;
  options.listen_address = "0.0.0.0";
  auto refused = ValidateProcessDutOptions(options);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("a listen address is for the TCP link"),
            std::string::npos);
  options.transport = DutLinkTransport::kTcp;
  EXPECT_TRUE(ValidateProcessDutOptions(options).ok());
}

// The runner with a DUT process that is killed mid-run: the run ends at once with a stop reason
// that names the kill, and Finish still builds the whole report.
TEST(ProcessDutRunTest, KilledDutEndsTheRunWithACompleteReport) {
  const auto spec =
      LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto");
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt,
                                          ::hilrig::test_support::SourceDir() + "/scenarios");
  ASSERT_TRUE(LoadTactileCalibration(config).ok());
  ProcessDut* process = nullptr;
  RunControl control;
  const rig::SteadyClock wall_clock;
  control.wall_clock = &wall_clock;
  control.dut_factory = [&](const ScenarioConfig& scene, std::unique_ptr<rig::CanBus> bus,
                            double control_period_s) -> rig::Result<std::unique_ptr<DutPort>> {
    ProcessDutOptions options = TestOptions();
    options.answer_timeout_s = 30;  // the kill must be noticed without the watchdog
    auto dut =
        std::make_unique<ProcessDut>(FirmwareFor(scene), std::move(bus), control_period_s, options);
    process = dut.get();
    return std::unique_ptr<DutPort>(std::move(dut));
  };
  ScenarioRunner runner(config, {}, control);
  ASSERT_NE(process, nullptr);
  for (int i = 0; i < 200; ++i) ASSERT_TRUE(runner.Tick());
  ASSERT_EQ(::kill(process->pid(), SIGKILL), 0);
  int more_ticks = 0;
  while (runner.Tick()) ++more_ticks;
  const proto::Report report = runner.Finish();
  EXPECT_LT(more_ticks, 10);  // the next control tick notices (control runs every tick or so)
  EXPECT_EQ(report.stop_reason(), "dut failed: dut process killed by signal 9");
  EXPECT_EQ(report.stop_kind(), proto::STOP_DUT_FAILED);
  EXPECT_FALSE(report.passed());
  EXPECT_GE(report.ticks(), 200u);
  bool has_link_metrics = false;
  for (const auto& metric : report.metrics()) {
    if (metric.name() == "link_commands_received") has_link_metrics = metric.value() > 0;
  }
  EXPECT_TRUE(has_link_metrics);
}

}  // namespace
}  // namespace hilrig::host
