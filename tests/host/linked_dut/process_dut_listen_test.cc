// `--dut listen:`: the rig starts no process and waits for a DUT the user starts to dial its TCP
// link with the token from a file. dut_emu, started here by hand as a user would, is that DUT.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <streambuf>
#include <string>
#include <thread>

#include "host/dut/firmware_config.h"
#include "host/link/child_process.h"
#include "host/link/hil_link_socket.h"
#include "host/link/link_token.h"
#include "host/linked_dut/process_dut.h"
#include "rig/emulated_bus.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
constexpr double kControlPeriodS = 1e-3;

// The notes of a launch in another thread, and a wait for their first line.
class NoteLines final : public std::streambuf {
 public:
  bool WaitForLine(std::chrono::seconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return line_.wait_for(lock, timeout, [this] { return text_.find('\n') != std::string::npos; });
  }
  std::string text() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return text_;
  }

 protected:
  int overflow(int c) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    text_ += static_cast<char>(c);
    if (c == '\n') line_.notify_all();
    return c;
  }

 private:
  std::mutex mutex_;
  std::condition_variable line_;
  std::string text_;
};

// A TCP port free a moment ago (the kernel's pick); the UDP bus takes the next one.
std::uint16_t FreePort() {
  auto listener = LinkListener::Listen("127.0.0.1", 0);
  return listener.ok() ? listener.value()->port() : 0;
}

ProcessDutOptions Listening(const fs::path& dir, double start_timeout_s) {
  ProcessDutOptions options;
  options.listen = true;
  options.transport = DutLinkTransport::kTcp;
  options.listen_port = FreePort();
  options.token_file = (dir / "token").string();
  options.start_timeout_s = start_timeout_s;
  return options;
}

DutFirmware HoverFirmware() {
  return DutFirmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true};
}

TEST(ProcessDutListenTest, ADutTheUserStartsDialsInWithTheTokenFromTheFile) {
  const fs::path dir = FreshTestDir("hilrig_listen_");
  NoteLines lines;
  std::ostream notes(&lines);
  ProcessDutOptions options = Listening(dir, 10);
  options.notes = &notes;
  rig::EmulatedBus bus;
  rig::Result<std::unique_ptr<ProcessDut>> dut = rig::MakeError("not launched");
  std::thread launcher([&] {
    dut = ProcessDut::Launch(HoverFirmware(), bus.Connect("dut"), kControlPeriodS, options);
  });
  ASSERT_TRUE(lines.WaitForLine(std::chrono::seconds(10)));
  const std::string port = std::to_string(options.listen_port);
  const std::string can = "udp:" + std::to_string(options.listen_port + 1) + ":1:2";
  EXPECT_NE(lines.text().find("start it with --link 127.0.0.1:" + port + " --can " + can +
                              " --token-file " + options.token_file + " (a new token)"),
            std::string::npos)
      << lines.text();
  auto user_dut =
      ChildProcess::Spawn({::hilrig::test_support::BinDir() + "/dut_emu", "--link",
                           "127.0.0.1:" + port, "--can", can, "--token-file", options.token_file});
  launcher.join();
  ASSERT_TRUE(user_dut.ok()) << user_dut.error().message;
  ASSERT_TRUE(dut.ok()) << dut.error().message;
  EXPECT_EQ(dut.value()->pid(), -1);  // no child of the rig's
  EXPECT_NE(dut.value()->description().find("a DUT that dialled 127.0.0.1:" + port + " over the"),
            std::string::npos)
      << dut.value()->description();
  dut.value()->Send(SetpointMessage{
      {0, 0}, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0});
  for (std::uint64_t tick = 1; tick <= 20; ++tick) {
    ASSERT_TRUE(dut.value()->Step(tick, static_cast<std::int64_t>(tick) * 1'000'000).ok()) << tick;
  }
  struct stat status {};
  ASSERT_EQ(::stat(options.token_file.c_str(), &status), 0);
  EXPECT_EQ(status.st_mode & 0777, 0600u);
  dut.value()->Stop();
}

TEST(ProcessDutListenTest, NoDutDiallingInIsANamedTimeout) {
  const fs::path dir = FreshTestDir("hilrig_listen_");
  const ProcessDutOptions options = Listening(dir, 0.3);
  rig::EmulatedBus bus;
  const auto dut =
      ProcessDut::Launch(HoverFirmware(), bus.Connect("dut"), kControlPeriodS, options);
  ASSERT_FALSE(dut.ok());
  EXPECT_EQ(dut.error().code, rig::ErrorCode::kTimeout);
  EXPECT_EQ(dut.error().message, "no DUT dialled 127.0.0.1:" + std::to_string(options.listen_port) +
                                     " with the token of " + options.token_file + " within 300 ms");
}

TEST(ProcessDutListenTest, AStopRequestEndsTheWait) {
  const fs::path dir = FreshTestDir("hilrig_listen_");
  ProcessDutOptions options = Listening(dir, 60);
  const std::atomic<bool> stop{true};
  options.stop_requested = &stop;
  rig::EmulatedBus bus;
  const auto start = std::chrono::steady_clock::now();
  const auto dut =
      ProcessDut::Launch(HoverFirmware(), bus.Connect("dut"), kControlPeriodS, options);
  ASSERT_FALSE(dut.ok());
  EXPECT_EQ(dut.error().code, rig::ErrorCode::kInterrupted);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

}  // namespace
}  // namespace hilrig::host
