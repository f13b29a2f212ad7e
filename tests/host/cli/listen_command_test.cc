// hilrig listen: a bad URI or missing --can is exit 2 naming the URI and the cause, and frames on
// a bus opened by URI come out as candump lines.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "rig/udp_bus.h"
#include "tests/support/cli_runner.h"

namespace hilrig::host {
namespace {

TEST(ListenCommandTest, AnUnknownSchemeIsBadInputNamingTheUri) {
  const CliResult result = Cli({"listen", "--can", "serial:/dev/ttyUSB0"});
  EXPECT_EQ(result.exit_code, kExitBadInput);
  EXPECT_NE(result.err.find("hilrig listen: CAN bus \"serial:/dev/ttyUSB0\": unknown scheme"),
            std::string::npos)
      << result.err;
  EXPECT_EQ(result.out, "");
}

TEST(ListenCommandTest, BadArgumentsAreBadInput) {
  const std::array<std::pair<std::vector<std::string>, const char*>, 4> cases = {{
      {{"listen"}, "--can URI is required"},
      {{"listen", "--can", "udp:0"}, "CAN bus \"udp:0\": UDP base port 0"},
      {{"listen", "--can", "socketcan"}, "CAN bus \"socketcan\": expected socketcan:IFACE"},
      {{"listen", "--can", "emulated", "--frames", "0"}, "--frames must be a whole number"},
  }};
  for (const auto& [args, message] : cases) {
    const CliResult result = Cli(args);
    EXPECT_EQ(result.exit_code, kExitBadInput) << args.back();
    EXPECT_NE(result.err.find(message), std::string::npos) << result.err;
  }
}

TEST(ListenCommandTest, PrintsTheFramesOnAUdpBusAsCandumpLines) {
  auto group = rig::OpenUdpBusGroup(2);
  ASSERT_TRUE(group.ok()) << group.error().message;
  std::vector<std::unique_ptr<rig::UdpBus>> nodes = std::move(group).value();
  const std::string uri = "udp:" + std::to_string(nodes[0]->local_port()) + ":1:2";
  nodes[1].reset();  // the command binds node 1

  std::atomic<bool> done{false};
  std::ostringstream out, err;
  int exit_code = -1;
  std::thread listener([&] {
    exit_code = RunCli({"listen", "--can", uri, "--frames", "1"}, out, err);
    done.store(true);
  });
  // Datagrams sent before the command binds its port are lost: send until it has printed one.
  const rig::CanFrame frame = rig::CanFrame::Classic(0x123, std::array<std::uint8_t, 2>{0xAB, 1});
  while (!done.load()) {
    (void)nodes[0]->Send(frame, 0);
    std::this_thread::yield();
  }
  listener.join();
  EXPECT_EQ(exit_code, kExitPass) << err.str();
  EXPECT_NE(out.str().find(" udp 123#AB01\n"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace hilrig::host
