// Waiting for PX4 SITL instead of starting the stand-in: the rig binds the simulator and API ports
// it is given, a flight stack the test starts dials them, and its first answers come late, as
// PX4's boot sends them (tests/host/linked_dut/mavlink_bad_peer.cc, mode late): those steps are
// answered at once, the late answers taken for outputs, and the steps after waited for.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <optional>
#include <sstream>
#include <string>

#include "host/dut/firmware_config.h"
#include "host/link/child_process.h"
#include "host/linked_dut/mavlink_dut.h"
#include "rig/clock.h"
#include "rig/emulated_bus.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

// A port the system has free now, of `type` (SOCK_STREAM or SOCK_DGRAM).
std::uint16_t FreePort(int type) {
  const int fd = ::socket(AF_INET, type, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  socklen_t length = sizeof address;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  ::close(fd);
  return ntohs(address.sin_port);
}

double Metric(const DutPort& dut, const std::string& name) {
  for (const rig::Metric& metric : dut.link_metrics()) {
    if (metric.name == name) return metric.value;
  }
  return -1;
}

TEST(MavlinkPx4SitlTest, AFlightStackThatAnswersLateIsNotWaitedForUntilItAnswers) {
  const std::uint16_t sim_port = FreePort(SOCK_STREAM);
  const std::uint16_t api_port = FreePort(SOCK_DGRAM);
  auto peer = ChildProcess::Spawn({::hilrig::test_support::BinDir() + "/mavlink_bad_peer",
                                   "--mavlink", "127.0.0.1:" + std::to_string(sim_port), "--api",
                                   "127.0.0.1:" + std::to_string(api_port), "--mode", "late"});
  ASSERT_TRUE(peer) << peer.error().message;
  rig::EmulatedBus bus;
  const rig::SteadyClock clock;
  std::ostringstream notes;
  MavlinkDutPortOptions options;
  options.link.start_stand_in = false;
  options.link.first_answers_late = true;
  options.link.sim_port = sim_port;
  options.link.api_port = api_port;
  options.link.start_timeout_s = 5;
  options.link.notes = &notes;
  options.session.clock = &clock;
  MavlinkDut dut(DutFirmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true},
                 bus.Connect("dut"), 1e-3, options);
  auto started = dut.Start();
  ASSERT_TRUE(started) << started.error().message;
  EXPECT_NE(notes.str().find("waiting up to 5 s for a flight stack on the MAVLink simulator link "
                             "tcp 127.0.0.1:" +
                             std::to_string(sim_port)),
            std::string::npos)
      << notes.str();
  EXPECT_NE(dut.description().find("PX4 SITL"), std::string::npos);
  for (std::uint64_t tick = 1; tick <= 400; ++tick) {
    const std::int64_t now_ns = std::int64_t(tick) * 1'000'000;
    dut.Send(ImuMessage{{tick - 1, now_ns},
                        Eigen::Vector3d(0.001 * double(tick % 5), 0, 0),
                        Eigen::Vector3d(0, 0, 9.81)});
    auto command = dut.Step(tick, now_ns);
    ASSERT_TRUE(command) << "tick " << tick << ": " << command.error().message;
    EXPECT_EQ(command.value().answers_sequence, tick);
  }
  // The 15 steps the stack held were answered at once, each after the 50 ms wait; their late
  // answers came in a burst with the 16th step's (on a busy machine, a step or two later), and
  // every step from there was waited for.
  const double late = Metric(dut, "mavlink_late_answers");
  EXPECT_GE(late, 15);
  EXPECT_LE(late, 20);
  EXPECT_EQ(Metric(dut, "mavlink_controls_received"), 100);
  dut.Stop();
}

}  // namespace
}  // namespace hilrig::host
