// The STM32F405 image on QEMU's netduinoplus2, driven over its two USARTs (QEMU ptys) as the
// runner drives a board: the handshake, TargetInfo with the image's own flash and RAM figures, and
// control steps with sensor-node frames on the bridge whose commands track the host's float
// DutCore fed the same inputs (newlib's and glibc's libm differ, so within a tolerance, not bit
// for bit), with the work per step measured inside the control period. Builds the image in a tree
// of its own first; skips without qemu-system-arm or the arm-none-eabi cross compiler.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "host/link/child_process.h"
#include "tests/support/serial_line_peer.h"
#include "tests/support/serial_step_script.h"
#include "tests/support/test_paths.h"

namespace hilrig::dut_fw {
namespace {

constexpr int kAnswerTimeoutMs = 5000;  // a bound on a hung target; answers take milliseconds
constexpr std::uint32_t kCyclesPerPeriod = 168'000'000 / 1000;

bool Installed(const std::string& tool) {
  return std::system(("command -v " + tool + " >/dev/null 2>&1").c_str()) == 0;
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class QemuSerialDutTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!Installed("qemu-system-arm") || !Installed("arm-none-eabi-g++")) {
      GTEST_SKIP() << "qemu-system-arm or arm-none-eabi-g++ not installed";
    }
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("hilrig_qemu_serial_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    const std::string build = "HILRIG_TARGET_BUILD_DIR=" + (dir_ / "build").string() + " " +
                              ::hilrig::test_support::SourceDir() + "/scripts/build-target -j1 >" +
                              (dir_ / "build.log").string() + " 2>&1";
    ASSERT_EQ(std::system(build.c_str()), 0) << ReadFile(dir_ / "build.log");
    image_ = dir_ / "build" / "dut_fw_stm32f405.elf";
    auto qemu = host::ChildProcess::Spawn(
        {"/bin/sh", "-c",
         "exec qemu-system-arm -M netduinoplus2 -display none -monitor none -icount shift=0 "
         "-kernel " +
             image_.string() + " -serial pty -serial pty </dev/null >" +
             (dir_ / "qemu.log").string() + " 2>&1"});
    ASSERT_TRUE(qemu.ok()) << qemu.error().message;
    qemu_.emplace(std::move(qemu).value());
    ASSERT_NO_FATAL_FAILURE(OpenPtys());
  }

  void TearDown() override {
    link_ = OwnedFd();
    bridge_ = OwnedFd();
    if (qemu_) qemu_->Terminate();
    if (!dir_.empty()) std::filesystem::remove_all(dir_);
  }

  // QEMU names the ptys of USART1 and USART2, in that order, on its output.
  void OpenPtys() {
    const std::regex redirected("char device redirected to (/dev/pts/[0-9]+)");
    std::vector<std::string> paths;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (paths.size() < 2 && std::chrono::steady_clock::now() < deadline) {
      paths.clear();
      const std::string log = ReadFile(dir_ / "qemu.log");
      for (auto it = std::sregex_iterator(log.begin(), log.end(), redirected);
           it != std::sregex_iterator(); ++it) {
        paths.push_back((*it)[1]);
      }
      ASSERT_FALSE(qemu_->PollExit()) << ReadFile(dir_ / "qemu.log");
      if (paths.size() < 2) ::usleep(20'000);  // a nap between looks at the log, not a wait
    }
    ASSERT_EQ(paths.size(), 2u) << ReadFile(dir_ / "qemu.log");
    link_ = OwnedFd(::open(paths[0].c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC));
    bridge_ = OwnedFd(::open(paths[1].c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC));
    ASSERT_GE(link_.get(), 0);
    ASSERT_GE(bridge_.get(), 0);
    MakeRaw(link_.get());
    MakeRaw(bridge_.get());
  }

  // Hello every 100 ms until the board answers, as the runner does (it may still be booting).
  std::optional<proto::LinkMessage> Handshake(SerialLinePeer& runner) {
    for (int attempt = 0; attempt < 50; ++attempt) {
      runner.Send(Hello());
      if (auto answer = runner.Receive(100)) return answer;
    }
    return std::nullopt;
  }

  std::filesystem::path dir_;
  std::filesystem::path image_;
  std::optional<host::ChildProcess> qemu_;
  OwnedFd link_;
  OwnedFd bridge_;
};

TEST_F(QemuSerialDutTest, AnswersTheRunnerAndStepsLikeTheHostFloatCore) {
  SerialLinePeer runner(link_.get());
  const auto hello = Handshake(runner);
  ASSERT_TRUE(hello && hello->has_hello()) << ReadFile(dir_ / "qemu.log");
  EXPECT_EQ(hello->hello().role(), proto::Hello::DUT);
  EXPECT_EQ(hello->hello().name(), "dut_fw stm32f405");

  runner.Send(Config(SixPadFirmware()));
  auto info = runner.Receive(kAnswerTimeoutMs);
  while (info && info->has_hello()) info = runner.Receive(kAnswerTimeoutMs);  // a later Hello's
  ASSERT_TRUE(info && info->has_target_info());
  const proto::TargetInfo& target = info->target_info();
  EXPECT_EQ(target.board(), "stm32f405");
  EXPECT_EQ(target.core_clock_hz(), 168'000'000u);
  // The image in flash is what objcopy puts in the .bin; RAM is .data + .bss, the rest stack.
  EXPECT_EQ(target.flash_used_bytes(),
            std::filesystem::file_size(dir_ / "build" / "dut_fw_stm32f405.bin"));
  EXPECT_GT(target.ram_used_bytes(), 4096u);
  EXPECT_EQ(target.ram_used_bytes() + target.stack_bytes(), 128u * 1024u);

  // The controller's arithmetic is the same code in float; only libm's last bits differ.
  DirectDut<float> direct(OverTheLink<float>(SixPadFirmware()));
  std::uint32_t max_work = 0;
  for (std::uint64_t tick = 0; tick < 200; ++tick) {
    SCOPED_TRACE(tick);
    const TickInputs in = InputsAt(tick);
    WriteAll(bridge_.get(), in.bridge);
    runner.Send(in.step);
    const auto answer = runner.Receive(kAnswerTimeoutMs);
    ASSERT_TRUE(answer && answer->has_serial_command());
    const proto::SerialCommand& command = answer->serial_command();
    const DutCoreOutput<float> out = direct.Step(tick);
    EXPECT_EQ(command.answers_tick(), tick);
    EXPECT_EQ(command.armed(), out.armed);
    ASSERT_EQ(command.rotor_thrust_n_size(), 4);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(command.rotor_thrust_n(i), out.rotor_thrust_n[i], 1e-3);
    EXPECT_NEAR(command.servo_angle_rad(), out.servo_angle_rad, 1e-4);
    max_work = std::max(max_work, command.work_cycles());
    EXPECT_GT(command.work_cycles(), 0u);
    if (command.has_counters()) {
      EXPECT_EQ(command.counters().bridge_frames(), (tick / 4 + 1) * 7);
      EXPECT_EQ(command.counters().bridge_bytes_missing(), 0u);
      EXPECT_EQ(command.counters().frames_bad_checksum(), 0u);
    }
    if (HasFailure()) break;
  }
  EXPECT_LT(max_work, kCyclesPerPeriod);
  std::cout << "qemu serial dut: max work " << max_work << " of " << kCyclesPerPeriod
            << " cycles per control period\n";
}

}  // namespace
}  // namespace hilrig::dut_fw
