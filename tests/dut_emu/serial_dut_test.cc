// dut_emu --serial on pseudo-terminals: the runner's side of the line is the test, the DUT's side
// is RunSerialDut in a thread with the link and the bridge on ttys in raw mode, as a real board's
// lines would be. The session itself is tested in tests/dut_link/serial_session_test.cc; this
// checks the tty plumbing: the spec, raw mode, both lines, a clean end.
#include "dut_emu/serial_dut.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <atomic>
#include <cstdlib>
#include <sstream>
#include <thread>

#include "dut_emu/dut_emu_server.h"
#include "tests/support/serial_line_peer.h"
#include "tests/support/serial_step_script.h"
#include "tests/support/stoppable_thread.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::dut_emu {
namespace {

using dut_fw::DirectDut;
using dut_fw::ExpectCommandIs;
using dut_fw::InputsAt;
using dut_fw::SerialLinePeer;
using dut_fw::SixPadFirmware;
using dut_fw::TickInputs;

constexpr int kAnswerTimeoutMs = 5000;  // a bound on a hung DUT; answers come in microseconds

TEST(SerialDutSpecTest, ParsesPathBaudAndBridge) {
  auto plain = ParseSerialSpec("/dev/ttyACM0");
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain.value().link_path, "/dev/ttyACM0");
  EXPECT_EQ(plain.value().baud, 2'000'000u);  // the firmware image's rates
  EXPECT_EQ(plain.value().bridge_baud, 921'600u);
  EXPECT_FALSE(plain.value().bridge_path.has_value());
  auto full = ParseSerialSpec("/dev/ttyACM0,baud=115200,bridge=/dev/ttyUSB0,bridge_baud=230400");
  ASSERT_TRUE(full.ok());
  EXPECT_EQ(full.value().baud, 115'200u);
  EXPECT_EQ(full.value().bridge_path, "/dev/ttyUSB0");
  EXPECT_EQ(full.value().bridge_baud, 230'400u);
  for (const char* bad : {"", ",baud=9600", "/dev/tty0,baud=12345", "/dev/tty0,baud=x",
                          "/dev/tty0,speed=9600", "/dev/tty0,bridge=", "/dev/tty0,bridge_baud=7"}) {
    EXPECT_FALSE(ParseSerialSpec(bad).ok()) << bad;
  }
}

TEST(SerialDutTest, RunsTheSessionOnPseudoTerminalsAndEndsWhenTheLineCloses) {
  dut_fw::Pty link = dut_fw::OpenPty();
  dut_fw::Pty bridge = dut_fw::OpenPty();
  SerialDutOptions options;
  options.link_path = link.slave_path;
  options.bridge_path = bridge.slave_path;
  std::ostringstream log;
  test_support::StoppableThread dut(
      [&](const std::atomic<bool>* stop) { return RunSerialDut(options, stop, log); });

  SerialLinePeer runner(link.master.get());
  runner.Send(dut_fw::Hello());
  const auto hello = runner.Receive(kAnswerTimeoutMs);
  ASSERT_TRUE(hello && hello->has_hello()) << log.str();
  EXPECT_EQ(hello->hello().role(), proto::Hello::DUT);
  EXPECT_EQ(hello->hello().name().rfind("dut_emu ", 0), 0u);
  runner.Send(dut_fw::Config(SixPadFirmware()));
  const auto info = runner.Receive(kAnswerTimeoutMs);
  ASSERT_TRUE(info && info->has_target_info()) << log.str();
  EXPECT_EQ(info->target_info().board(), "host");

  DirectDut<float> direct(dut_fw::OverTheLink<float>(SixPadFirmware()));
  for (std::uint64_t tick = 0; tick < 120; ++tick) {
    SCOPED_TRACE(tick);
    const TickInputs in = InputsAt(tick);
    dut_fw::WriteAll(bridge.master.get(), in.bridge);
    runner.Send(in.step);
    const auto answer = runner.Receive(kAnswerTimeoutMs);
    ASSERT_TRUE(answer && answer->has_serial_command()) << log.str();
    ExpectCommandIs(answer->serial_command(), direct.Step(tick), tick);
    EXPECT_EQ(answer->serial_command().work_cycles(), 0u);
    if (answer->serial_command().has_counters()) {
      EXPECT_EQ(answer->serial_command().counters().bridge_bytes_missing(), 0u);
      EXPECT_EQ(answer->serial_command().counters().bridge_frames(), (tick / 4 + 1) * 7);
    }
    if (HasFailure()) break;
  }

  // Bye ends the run; the next runner's Hello is answered (so the Bye was taken), and the line
  // going away between runs ends dut_emu cleanly.
  runner.Send(dut_fw::Bye());
  runner.Send(dut_fw::Hello());
  const auto again = runner.Receive(kAnswerTimeoutMs);
  ASSERT_TRUE(again && again->has_hello()) << log.str();
  link.slave.Close();
  link.master.Close();
  EXPECT_EQ(dut.Join(), kExitOk) << log.str();
  EXPECT_NE(log.str().find("closed"), std::string::npos) << log.str();
}

TEST(SerialDutTest, TheLineClosingMidRunIsAFailure) {
  dut_fw::Pty link = dut_fw::OpenPty();
  SerialDutOptions options;
  options.link_path = link.slave_path;
  std::ostringstream log;
  test_support::StoppableThread dut(
      [&](const std::atomic<bool>* stop) { return RunSerialDut(options, stop, log); });
  SerialLinePeer runner(link.master.get());
  runner.Send(dut_fw::Hello());
  ASSERT_TRUE(runner.Receive(kAnswerTimeoutMs));
  runner.Send(dut_fw::Config(SixPadFirmware()));
  const auto info = runner.Receive(kAnswerTimeoutMs);
  ASSERT_TRUE(info && info->has_target_info()) << log.str();
  link.slave.Close();
  link.master.Close();
  EXPECT_EQ(dut.Join(), kExitFailed) << log.str();
}

TEST(SerialDutTest, PutsBothLinesInRawModeAndEndsOnAStopRequest) {
  dut_fw::Pty link = dut_fw::OpenPty(/*raw=*/false);
  dut_fw::Pty bridge = dut_fw::OpenPty(/*raw=*/false);
  SerialDutOptions options;
  options.link_path = link.slave_path;
  options.bridge_path = bridge.slave_path;
  std::atomic<bool> stop{true};
  std::ostringstream log;
  EXPECT_EQ(RunSerialDut(options, &stop, log), kExitOk);
  // Each line at its own default rate: the link at 2 Mbaud, the bridge at 921600.
  for (const auto& [fd, speed] : {std::pair{link.slave.get(), speed_t(B2000000)},
                                  std::pair{bridge.slave.get(), speed_t(B921600)}}) {
    termios mode{};
    ASSERT_EQ(::tcgetattr(fd, &mode), 0);
    EXPECT_EQ(mode.c_lflag & (ICANON | ECHO | ISIG | IEXTEN), 0u);
    EXPECT_EQ(mode.c_iflag & (ICRNL | IXON | ISTRIP), 0u);
    EXPECT_EQ(mode.c_oflag & OPOST, 0u);
    EXPECT_EQ(mode.c_cflag & CSIZE, tcflag_t(CS8));
    EXPECT_EQ(::cfgetospeed(&mode), speed);
  }
}

TEST(SerialDutTest, ALineThatIsNoTerminalIsRefusedWithThePath) {
  SerialDutOptions options;
  options.link_path = "/dev/null";
  std::ostringstream log;
  EXPECT_EQ(RunSerialDut(options, nullptr, log), kExitFailed);
  EXPECT_NE(log.str().find("/dev/null"), std::string::npos) << log.str();
}

// The executable: --serial needs no link token, and a bad spec is a usage error that says why.
TEST(DutEmuSerialMainTest, TakesNoTokenAndRefusesABadSpecAsUsage) {
  const auto err = host::FreshTestDir("dut_emu_serial_") / "err";
  const std::string dut_emu =
      "env -u HILRIG_LINK_TOKEN " + ::hilrig::test_support::BinDir() + "/dut_emu --serial ";
  const int bad = std::system((dut_emu + "/dev/null,baud=7 2> " + err.string()).c_str());
  ASSERT_TRUE(WIFEXITED(bad));
  EXPECT_EQ(WEXITSTATUS(bad), kExitUsage);
  EXPECT_NE(host::ReadFile(err).find("dut_emu: --serial baud=7: not a rate termios has"),
            std::string::npos)
      << host::ReadFile(err);
  const int no_tty = std::system((dut_emu + "/nonexistent/tty 2> " + err.string()).c_str());
  ASSERT_TRUE(WIFEXITED(no_tty));
  EXPECT_EQ(WEXITSTATUS(no_tty), kExitFailed);
  EXPECT_NE(host::ReadFile(err).find("cannot open /nonexistent/tty: No such file or directory"),
            std::string::npos)
      << host::ReadFile(err);
}

}  // namespace
}  // namespace hilrig::dut_emu
