// `hilrig run --dut serial:` end to end without a board: the runner opens the slave sides of two
// pseudo-terminal pairs as its HIL line and sensor bridge, and a thread plays a board on the master
// sides (the kernel's tty layer in between, as for a USB serial adapter). The thread answers the
// handshake with a TargetInfo and each step with a fixed command and a work figure, and reads the
// bridge; the run completes and its report carries the target section and both lines' counts.
#include <fcntl.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <thread>

#include "host/cli/cli.h"
#include "host/link/fd_byte_stream.h"
#include "host/link/line_link.h"
#include "proto/report.pb.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

// The slave stays open here too: a master whose slave nobody holds reads as hung up.
struct PtyPair {
  int master = -1;
  int slave = -1;
  std::string slave_path;
  PtyPair() {
    std::array<char, 128> name{};
    if (::openpty(&master, &slave, name.data(), nullptr, nullptr) != 0) return;
    slave_path = name.data();
    ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
  }
  ~PtyPair() {
    ::close(master);
    ::close(slave);
  }
};

// The board: serves until the runner says Bye, or, once the run is over, until the line has been
// quiet for a while; then it reads what is left on the bridge. The two pseudo-terminals deliver
// independently, so a step may arrive before the bridge bytes written ahead of it, and a run in
// real time returns before the board has read its last steps.
struct PtyBoard {
  std::atomic<std::uint64_t> steps{0};  // distinct ticks: a retried step counts once
  std::atomic<std::uint64_t> bridge_bytes{0};
  std::atomic<std::uint64_t> announced_bridge_bytes{0};
  std::atomic<bool> bye{false};
  std::atomic<bool> stop{false};  // the run is over, whatever it said

  static constexpr int kQuietLineMs = 200;

  void Serve(int link_fd, int bridge_fd) {
    FdByteStream line(link_fd, false, "board link", nullptr);
    FdByteStream bridge(bridge_fd, false, "board bridge", nullptr);
    LineLink link(line);
    std::uint64_t last_tick = ~std::uint64_t{0};
    while (!bye) {
      ReadBridge(bridge);
      const bool run_over = stop;
      const LineReceived received = link.Receive(run_over ? kQuietLineMs : 1000);
      if (received.status == LineReceiveStatus::kTimeout) {
        if (run_over) break;
        continue;
      }
      if (received.status != LineReceiveStatus::kMessage) break;
      const proto::LinkMessage& message = received.message;
      if (message.has_bye()) {
        bye = true;
        break;
      }
      if (message.has_serial_step() && message.serial_step().tick() != last_tick) {
        last_tick = message.serial_step().tick();
        ++steps;
        announced_bridge_bytes += message.serial_step().bridge_bytes();
      }
      if (!link.Send(Answer(message), 1000)) break;
    }
    ReadBridgeUntilQuiet(bridge);
  }

  void ReadBridge(FdByteStream& bridge) {
    std::array<std::uint8_t, 512> chunk;
    for (StreamRead read = bridge.ReadSome(chunk, 0); read.status == StreamStatus::kData;
         read = bridge.ReadSome(chunk, 0)) {
      bridge_bytes += read.bytes;
    }
  }

  void ReadBridgeUntilQuiet(FdByteStream& bridge) {
    std::array<std::uint8_t, 512> chunk;
    for (StreamRead read = bridge.ReadSome(chunk, kQuietLineMs); read.status == StreamStatus::kData;
         read = bridge.ReadSome(chunk, kQuietLineMs)) {
      bridge_bytes += read.bytes;
    }
  }

  static proto::LinkMessage Answer(const proto::LinkMessage& message) {
    proto::LinkMessage answer;
    if (message.has_hello()) {
      answer.mutable_hello()->set_role(proto::Hello::DUT);
      answer.mutable_hello()->mutable_header()->set_protocol_version(1);
    } else if (message.has_config()) {
      answer.mutable_target_info()->set_board("pty board");
      answer.mutable_target_info()->set_core_clock_hz(168'000'000);
    } else if (message.has_serial_step()) {
      proto::SerialCommand* command = answer.mutable_serial_command();
      command->set_answers_tick(message.serial_step().tick());
      for (int rotor = 0; rotor < 4; ++rotor) command->add_rotor_thrust_n(0);
      for (int axis = 0; axis < 3; ++axis) command->add_estimated_position_m(0);
      for (int axis = 0; axis < 3; ++axis) command->add_external_force_world_n(0);
      command->set_work_cycles(16'800);
    }
    return answer;
  }
};

std::filesystem::path PadsScene(const std::filesystem::path& dir) {
  const std::filesystem::path spec = dir / "pads.textproto";
  std::ofstream(spec) << "name: \"pads\"\n"
                         "models { tactile { enabled: true field_fidelity: \"tiles:8\" } }\n"
                         "vehicle { initial_position_m { z: 1 } }\n"
                         "simulation { duration_s: 0.5 }\n";
  return spec;
}

// What a run against the board showed on both ends.
struct BoardRun {
  CliResult cli;
  proto::Report report;
  std::uint64_t steps = 0;
  std::uint64_t bridge_bytes = 0;
  std::uint64_t announced_bridge_bytes = 0;
  bool bye = false;
};

// Runs the pads scene with `options` against a board on two pseudo-terminal pairs; `line` is
// appended to the link device in the serial: spec (",baud=N").
BoardRun RunAgainstABoard(const std::string& name, std::vector<std::string> options,
                          const std::string& line) {
  const std::filesystem::path dir = FreshTestDir(name);
  PtyPair link;
  PtyPair bridge;
  EXPECT_GE(link.master, 0);
  EXPECT_GE(bridge.master, 0);
  PtyBoard board;
  std::thread serving([&] { board.Serve(link.master, bridge.master); });
  std::vector<std::string> args = {
      "run",   PadsScene(dir).string(),
      "--out", (dir / "out").string(),
      "--dut", "serial:" + link.slave_path + line + ",bridge=" + bridge.slave_path};
  args.insert(args.end(), options.begin(), options.end());
  BoardRun run;
  run.cli = Cli(args);
  board.stop = true;
  serving.join();
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(ReadFile(dir / "out" / "report.json"),
                                                          &run.report)
                  .ok())
      << run.cli.err;
  run.steps = board.steps;
  run.bridge_bytes = board.bridge_bytes;
  run.announced_bridge_bytes = board.announced_bridge_bytes;
  run.bye = board.bye;
  return run;
}

double Metric(const proto::Report& report, const std::string& name) {
  for (const proto::Metric& metric : report.metrics()) {
    if (metric.name() == name) return metric.value();
  }
  return -1;
}

TEST(CliSerialPtyTest, RunsAScenarioAgainstABoardOnAPseudoTerminal) {
  const BoardRun run = RunAgainstABoard("cli_serial_pty", {"--no-reference"}, ",baud=115200");
  const proto::Report& report = run.report;
  EXPECT_EQ(report.stop_reason(), "completed") << run.cli.err;
  EXPECT_EQ(run.steps, 500u);  // 0.5 s of 1 kHz control
  EXPECT_TRUE(run.bye);
  ASSERT_TRUE(report.has_target());
  EXPECT_EQ(report.target().board(), "pty board");
  EXPECT_EQ(report.target().steps_measured(), 500u);
  EXPECT_DOUBLE_EQ(report.target().work_p99_fraction(), 0.1);
  EXPECT_GT(run.bridge_bytes, 0u);  // the pads' CAN frames crossed the bridge
  EXPECT_EQ(run.bridge_bytes, run.announced_bridge_bytes);
  EXPECT_NE(run.cli.out.find("target pty board at 168 MHz"), std::string::npos) << run.cli.out;
  EXPECT_EQ(Metric(report, "line_commands_received"), 500);
}

// Real time: the steps go out without waiting, and the commands are polled as they come.
TEST(CliSerialPtyTest, RunsInRealTimeOverThePseudoTerminal) {
  const BoardRun run =
      RunAgainstABoard("cli_serial_pty_rt", {"--realtime", "--rt-priority", "0"}, "");
  const proto::Report& report = run.report;
  EXPECT_EQ(report.stop_reason(), "completed") << run.cli.err;
  EXPECT_EQ(report.timing().mode(), "realtime");
  EXPECT_EQ(run.steps, 500u);
  ASSERT_TRUE(report.has_target());
  EXPECT_GT(report.target().steps_measured(), 400u);  // a late command may be superseded
  EXPECT_EQ(run.bridge_bytes, run.announced_bridge_bytes);
}

}  // namespace
}  // namespace hilrig::host
