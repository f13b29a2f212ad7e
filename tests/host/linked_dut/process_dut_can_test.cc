// ProcessDut on a bus named by ProcessDutOptions::can_uri: the runner's CAN frames go out on the
// bus that URI opens, and dut_emu is started with the same URI. No SocketCAN interface exists where
// these tests run, so the forwarder's opener hands out node 0 of a loopback UDP bus instead, and a
// wrapper in dut_emu's place records the arguments it got and runs dut_emu on node 1 of that bus.
// A lockstep step that announces a frame fails unless the frame reaches dut_emu, so a step that
// succeeds says the frame crossed the opened bus. Frames over a real vcan0 are the VM test's.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "host/dut/firmware_config.h"
#include "host/linked_dut/process_dut.h"
#include "rig/emulated_bus.h"
#include "rig/udp_bus.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

constexpr double kControlPeriodS = 1e-3;
constexpr const char* kBenchUri = "socketcan:vcan7";

// A dut_emu that writes its arguments to DIR/argv, then runs dut_emu on `dut_can_uri` instead of
// the bus it was told.
fs::path WriteDutEmuWrapper(const fs::path& dir, const std::string& dut_can_uri) {
  const fs::path wrapper = dir / "dut_emu_wrapper.sh";
  std::ofstream(wrapper) << "#!/bin/sh\n"
                         << "printf '%s\\n' \"$@\" > '" << (dir / "argv").string() << "'\n"
                         << "link=\"$2\"\nshift 4\n"
                         << "exec '" + ::hilrig::test_support::BinDir() +
                                "/dut_emu' --link \"$link\" --can '"
                         << dut_can_uri << "' \"$@\"\n";
  fs::permissions(wrapper, fs::perms::owner_all);
  return wrapper;
}

TEST(ProcessDutCanTest, ForwardsTheRunnersFramesOverTheBusItsUriOpens) {
  const fs::path dir = FreshTestDir("process_dut_can_");
  auto bench = rig::OpenUdpBusGroup(2);
  ASSERT_TRUE(bench.ok()) << bench.error().message;
  const std::uint16_t bench_port = bench.value()[0]->local_port();
  // std::function wants a copyable opener; the node goes to the first call.
  auto forwarder_end = std::make_shared<std::unique_ptr<rig::CanBus>>(std::move(bench.value()[0]));
  bench.value()[1].reset();  // dut_emu's node

  ProcessDutOptions options;
  options.transport = DutLinkTransport::kTcp;  // the wrapper knows the TCP command line
  options.dut_emu_path =
      WriteDutEmuWrapper(dir, "udp:" + std::to_string(bench_port) + ":1:2").string();
  options.can_uri = kBenchUri;
  std::vector<std::string> opened;
  options.open_can_bus = [&](const std::string& uri) -> rig::Result<std::unique_ptr<rig::CanBus>> {
    opened.push_back(uri);
    if (!*forwarder_end) return rig::MakeError("the bench bus was opened twice");
    return std::move(*forwarder_end);
  };
  rig::EmulatedBus runner_bus;
  auto hall_node = runner_bus.Connect("hall");
  const DutFirmware firmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true};
  auto dut = ProcessDut::Launch(firmware, runner_bus.Connect("dut"), kControlPeriodS, options);
  ASSERT_TRUE(dut.ok()) << dut.error().message;

  const std::array<std::uint8_t, 3> payload = {7, 8, 9};
  ASSERT_TRUE(hall_node->Send(rig::CanFrame::Classic(0x123, payload), 0).ok());
  auto answer = dut.value()->Step(1, 1'000'000);
  ASSERT_TRUE(answer.ok()) << answer.error().message;
  EXPECT_EQ(dut.value()->counters().can_frames_received, 1u);
  // dut_emu's front end counted the frame itself: 0x123 is no sensor node's, so it rejected it.
  EXPECT_TRUE(dut.value()->counters().front_end_counted);
  EXPECT_EQ(dut.value()->counters().can_frames_rejected, 1u);
  EXPECT_EQ(dut.value()->counters().sensor_samples, 0u);

  EXPECT_EQ(opened, std::vector<std::string>{kBenchUri});
  EXPECT_NE(ReadFile(dir / "argv").find("--can\n" + std::string(kBenchUri) + "\n"),
            std::string::npos)
      << ReadFile(dir / "argv");
  EXPECT_NE(dut.value()->description().find(std::string("CAN frames over ") + kBenchUri),
            std::string::npos)
      << dut.value()->description();
}

TEST(ProcessDutCanTest, RefusesBusesTwoProcessesCannotShare) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"udp:30000", "the rig chooses the run's own UDP bus"},
      {"emulated", "an emulated bus lives inside one process"},
      {"gs_usb:ABC", "one process claims a gs_usb adapter"},
      {"serial:/dev/ttyUSB0", "unknown scheme \"serial\""},
      {"socketcan", "expected socketcan:IFACE"},
  };
  for (const auto& [uri, why] : cases) {
    ProcessDutOptions options;
    options.can_uri = uri;
    auto valid = ValidateProcessDutOptions(options);
    ASSERT_FALSE(valid.ok()) << uri;
    EXPECT_NE(valid.error().message.find("CAN bus \"" + uri + "\": "), std::string::npos)
        << valid.error().message;
    EXPECT_NE(valid.error().message.find(why), std::string::npos) << valid.error().message;
  }
  ProcessDutOptions bench;
  bench.can_uri = kBenchUri;
  EXPECT_TRUE(ValidateProcessDutOptions(bench).ok());
}

}  // namespace
}  // namespace hilrig::host
