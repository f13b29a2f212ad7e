// What every DutPort does, run against each one the rig has: the in-process firmware in double
// and in float, dut_emu over the shared-memory and the TCP link, dut_emu --serial on a pair of
// pseudo-terminals, a program that dials the line link (examples/hover_dut, a controller of its
// own), PX4's stand-in over MAVLink (dut_emu --mavlink, lockstep only), and the firmware image
// on QEMU (skipped without qemu-system-arm or the image). The
// contract is dut_port.h's: Start once, then every tick asked for is answered with that tick's
// command, in lockstep and through RequestStep and PollCommand; ticks only go forward; after
// Stop a step is an error, not a hang; Stop may come twice, or without a start; the inputs are
// counted. A port whose controller is dut_fw gives the in-process firmware's command, to the
// float precision of its link.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "host/dut/firmware_config.h"
#include "host/dut/in_process_dut.h"
#include "host/link/child_process.h"
#include "host/link/fd_byte_stream.h"
#include "host/linked_dut/dialed_lines.h"
#include "host/linked_dut/mavlink_dut.h"
#include "host/linked_dut/process_dut.h"
#include "host/linked_dut/serial_dut.h"
#include "host/linked_dut/serial_lines.h"
#include "rig/clock.h"
#include "rig/emulated_bus.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

constexpr double kControlPeriodS = 1e-3;
constexpr std::uint64_t kTicks = 60;

// How a port's commands compare with the in-process firmware's.
enum class Controller {
  kDutFwDouble,  // dut_fw in double precision, with double inputs: bit for bit
  kDutFwFloat,   // dut_fw in float, or fed over a link of floats: to float precision
  kOwn,          // a controller of its own, or dut_fw at another rate: only the contract
};

struct PortKind {
  std::string name;
  Controller controller;
  bool realtime = true;  // false: lockstep only, and real time refused when the port is made
};

std::string NameOf(const ::testing::TestParamInfo<PortKind>& info) { return info.param.name; }
void PrintTo(const PortKind& kind, std::ostream* out) { *out << kind.name; }

DutFirmware HoverFirmware() {
  return DutFirmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true};
}

// A pseudo-terminal pair whose slave stays open here too: a master whose slave nobody holds
// reads as hung up while the DUT is still opening it.
struct Pty {
  int master = -1;
  int slave = -1;
  std::string slave_path;
};

rig::Result<std::shared_ptr<Pty>> OpenPty() {
  auto pty = std::shared_ptr<Pty>(new Pty, [](Pty* p) {
    if (p->master >= 0) ::close(p->master);
    if (p->slave >= 0) ::close(p->slave);
    delete p;
  });
  std::array<char, 128> name{};
  if (::openpty(&pty->master, &pty->slave, name.data(), nullptr, nullptr) != 0) {
    return rig::MakeError("openpty failed");
  }
  ::fcntl(pty->master, F_SETFL, ::fcntl(pty->master, F_GETFL) | O_NONBLOCK);
  pty->slave_path = name.data();
  return pty;
}

// dut_emu --serial on two pseudo-terminal pairs, the runner on their masters.
SerialLineOpener DutEmuOnPtys() {
  return [](double) -> rig::Result<SerialLines> {
    auto link = OpenPty();
    auto bridge = OpenPty();
    if (!link || !bridge) return rig::MakeError("no pseudo-terminal");
    auto child =
        ChildProcess::Spawn({::hilrig::test_support::BinDir() + "/dut_emu", "--serial",
                             link.value()->slave_path + ",bridge=" + bridge.value()->slave_path});
    if (!child) return child.error();
    SerialLines lines;
    lines.link =
        std::make_unique<FdByteStream>(link.value()->master, false, "pty link", link.value());
    lines.bridge =
        std::make_unique<FdByteStream>(bridge.value()->master, false, "pty bridge", bridge.value());
    lines.emulator = std::move(child).value();
    lines.description = "dut_emu --serial on pseudo-terminals";
    return lines;
  };
}

class DutPortConformanceTest : public ::testing::TestWithParam<PortKind> {
 protected:
  // The port of this kind on the test's bus; null, with skip_ saying why, when the machine lacks
  // what it needs.
  std::unique_ptr<DutPort> Make(DutPacing pacing = DutPacing::kLockstep) {
    const std::string& kind = GetParam().name;
    std::unique_ptr<rig::CanBus> endpoint = bus_.Connect("dut");
    if (kind == "inproc") {
      return std::make_unique<InProcessDut>(HoverFirmware(), std::move(endpoint), kControlPeriodS);
    }
    if (kind == "inproc_float") {
      return std::make_unique<SinglePrecisionInProcessDut>(
          BasicDutFirmware<float>{
              FirmwareParamsFor<float>(QuadrotorParams{}), std::nullopt, {}, true},
          std::move(endpoint), kControlPeriodS);
    }
    if (kind == "process_shm" || kind == "process_tcp") {
      ProcessDutOptions options;
      options.dut_emu_path = ::hilrig::test_support::BinDir() + "/dut_emu";
      options.transport =
          kind == "process_tcp" ? DutLinkTransport::kTcp : DutLinkTransport::kSharedMemory;
      options.wall_clock = &wall_clock_;
      options.pacing = pacing;
      return std::make_unique<ProcessDut>(HoverFirmware(), std::move(endpoint), kControlPeriodS,
                                          options);
    }
    if (kind == "mavlink_emu") {
      MavlinkDutPortOptions options;
      options.link.dut_emu_path = ::hilrig::test_support::BinDir() + "/dut_emu";
      options.session.clock = &wall_clock_;
      options.session.pacing = pacing;
      return std::make_unique<MavlinkDut>(HoverFirmware(), std::move(endpoint), kControlPeriodS,
                                          options);
    }
    SerialDutOptions serial;
    serial.clock = &wall_clock_;
    serial.pacing = pacing;
    if (kind == "serial_pty") {
      return std::make_unique<SerialDut>(HoverFirmware(), std::move(endpoint), kControlPeriodS,
                                         DutEmuOnPtys(), serial);
    }
    if (kind == "line_exec") {
      DialedLineSpec spec;
      spec.program = ::hilrig::test_support::BinDir() + "/hover_dut";
      return std::make_unique<SerialDut>(HoverFirmware(), std::move(endpoint), kControlPeriodS,
                                         DialedLines(spec), serial);
    }
    // qemu: the image ./scripts/build-target makes, in virtual time.
#ifdef HILRIG_SANITIZED_BUILD
    skip_ = "the sanitizer build runs no emulated target";
    return nullptr;
#endif
    auto image = FindTargetImage(std::nullopt);
    auto qemu = FindInPath("qemu-system-arm");
    if (!image || !qemu) {
      skip_ = "no firmware image or no qemu-system-arm";
      return nullptr;
    }
    serial.answer_timeout_s = 10;
    serial.step_retry_s = 1;
    return std::make_unique<SerialDut>(HoverFirmware(), std::move(endpoint), kControlPeriodS,
                                       QemuLines({image.value(), qemu.value()}), serial);
  }

  // The hover inputs up to `tick`: a pose and the setpoint first, an IMU sample every tick.
  void SendInputs(DutPort& dut, std::uint64_t tick) {
    const std::int64_t now_ns = std::int64_t(tick) * 1'000'000;
    if (tick == 1) {
      dut.Send(VioMessage{{0, 0}, 0, Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity()});
      dut.Send(SetpointMessage{{0, 0},
                               Eigen::Vector3d(0, 0, 1.2),
                               Eigen::Vector3d::Zero(),
                               Eigen::Vector3d::Zero(),
                               0.3});
    }
    dut.Send(ImuMessage{{tick - 1, now_ns},
                        Eigen::Vector3d(0.01, -0.02, 0.003),
                        Eigen::Vector3d(0.1, 0, QuadrotorParams{}.gravity_m_s2)});
  }

  // Ticks 1..kTicks in lockstep; the last command.
  ActuatorMessage FlyLockstep(DutPort& dut) {
    ActuatorMessage last;
    for (std::uint64_t tick = 1; tick <= kTicks; ++tick) {
      SendInputs(dut, tick);
      auto command = dut.Step(tick, std::int64_t(tick) * 1'000'000);
      EXPECT_TRUE(command.ok()) << "tick " << tick << ": " << command.error().message;
      if (!command) return last;
      EXPECT_EQ(command.value().answers_sequence, tick);
      for (const double thrust : command.value().rotor_thrust_n) EXPECT_TRUE(std::isfinite(thrust));
      last = command.value();
    }
    return last;
  }

  rig::EmulatedBus bus_;
  rig::SteadyClock wall_clock_;
  std::string skip_;
};

TEST_P(DutPortConformanceTest, AnswersEveryTickItIsAskedFor) {
  auto dut = Make();
  if (!dut) GTEST_SKIP() << skip_;
  ASSERT_TRUE(dut->Start().ok());
  const ActuatorMessage last = FlyLockstep(*dut);
  EXPECT_EQ(last.answers_sequence, kTicks);
  EXPECT_TRUE(last.armed);
  dut->Stop();
}

TEST_P(DutPortConformanceTest, GivesTheInProcessFirmwaresCommand) {
  if (GetParam().controller == Controller::kOwn) GTEST_SKIP() << "a controller of its own";
  rig::EmulatedBus reference_bus;
  InProcessDut reference(HoverFirmware(), reference_bus.Connect("dut"), kControlPeriodS);
  const ActuatorMessage expected = FlyLockstep(reference);
  auto dut = Make();
  if (!dut) GTEST_SKIP() << skip_;
  ASSERT_TRUE(dut->Start().ok());
  const ActuatorMessage actual = FlyLockstep(*dut);
  for (std::size_t i = 0; i < actual.rotor_thrust_n.size(); ++i) {
    if (GetParam().controller == Controller::kDutFwDouble) {
      EXPECT_EQ(actual.rotor_thrust_n[i], expected.rotor_thrust_n[i]) << "rotor " << i;
    } else {
      EXPECT_NEAR(actual.rotor_thrust_n[i], expected.rotor_thrust_n[i],
                  1e-4 * std::abs(expected.rotor_thrust_n[i]) + 1e-5)
          << "rotor " << i;
    }
  }
  dut->Stop();
}

TEST_P(DutPortConformanceTest, ARealTimeRequestIsAnsweredByAPoll) {
  auto dut = Make(DutPacing::kRealtime);
  if (dut && !GetParam().realtime) {
    EXPECT_FALSE(dut->Start()) << "a lockstep-only port must refuse real time";
    return;
  }
  if (!dut) GTEST_SKIP() << skip_;
  ASSERT_TRUE(dut->Start().ok());
  SendInputs(*dut, 1);
  dut->RequestStep(1, 1'000'000);
  std::optional<ActuatorMessage> command;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!command && std::chrono::steady_clock::now() < deadline) {
    auto polled = dut->PollCommand();
    ASSERT_TRUE(polled.ok()) << polled.error().message;
    command = polled.value();
    if (!command) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(command.has_value()) << "no answer within 10 s";
  EXPECT_EQ(command->answers_sequence, 1u);
  dut->Stop();
}

TEST_P(DutPortConformanceTest, TicksOnlyGoForward) {
  auto dut = Make();
  if (!dut) GTEST_SKIP() << skip_;
  ASSERT_TRUE(dut->Start().ok());
  SendInputs(*dut, 1);
  ASSERT_TRUE(dut->Step(5, 5'000'000).ok());
  EXPECT_FALSE(dut->Step(5, 5'000'000).ok());
  EXPECT_FALSE(dut->Step(3, 3'000'000).ok());
  dut->Stop();
}

TEST_P(DutPortConformanceTest, AStepAfterStopIsAnError) {
  auto dut = Make();
  if (!dut) GTEST_SKIP() << skip_;
  ASSERT_TRUE(dut->Start().ok());
  SendInputs(*dut, 1);
  ASSERT_TRUE(dut->Step(1, 1'000'000).ok());
  dut->Stop();
  dut->Stop();
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(dut->Step(2, 2'000'000).ok());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_FALSE(dut->description().empty());
}

TEST_P(DutPortConformanceTest, StopWithoutStartIsHarmless) {
  auto dut = Make();
  if (!dut) GTEST_SKIP() << skip_;
  dut->Stop();
  EXPECT_FALSE(dut->Step(1, 1'000'000).ok());
}

TEST_P(DutPortConformanceTest, CountsTheInputsItIsSent) {
  auto dut = Make();
  if (!dut) GTEST_SKIP() << skip_;
  ASSERT_TRUE(dut->Start().ok());
  FlyLockstep(*dut);
  EXPECT_EQ(dut->counters().imu_messages, kTicks);
  EXPECT_EQ(dut->counters().vio_messages, 1u);
  dut->Stop();
}

INSTANTIATE_TEST_SUITE_P(EveryPort, DutPortConformanceTest,
                         ::testing::Values(PortKind{"inproc", Controller::kDutFwDouble},
                                           PortKind{"inproc_float", Controller::kDutFwFloat},
                                           PortKind{"process_shm", Controller::kDutFwDouble},
                                           PortKind{"process_tcp", Controller::kDutFwDouble},
                                           PortKind{"serial_pty", Controller::kDutFwFloat},
                                           PortKind{"line_exec", Controller::kOwn},
                                           PortKind{"mavlink_emu", Controller::kOwn, false},
                                           PortKind{"qemu", Controller::kDutFwFloat}),
                         NameOf);

}  // namespace
}  // namespace hilrig::host
