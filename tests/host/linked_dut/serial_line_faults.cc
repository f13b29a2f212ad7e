// The real-board code path without a board, as three processes: `hilrig run --dut serial:` on
// the host side of a null modem (tests/tools/pty_null_modem.cc: a pseudo-terminal pair for each
// side of the HIL link and of the sensor bridge), `dut_emu --serial` (the firmware's serial
// session, float) on the DUT side. A clean line runs balloon_grasp to its verdict and close to the
// host's own DUT; a line that drops, flips and inserts a few bytes costs a retry per damaged
// frame, not the run, and the trace stays as close; a line that damages every twentieth byte, or
// a DUT that dies, stops the run by name with a complete report folder, never a hang. Every wait
// is for an event (a line the null modem prints, a process's exit) with a bound.
#include <gmock/gmock.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cinttypes>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "host/mavlink/mavlink_messages.h"
#include "proto/report.pb.h"
#include "rig/clock.h"
#include "tests/support/child_waits.h"
#include "tests/support/serial_line_peer.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

constexpr double kStartBoundS = 10;  // the relay and dut_emu come up in milliseconds
constexpr double kRunBoundS = 90;    // a hang, not a slow machine, runs into this
constexpr const char* kExitedOk = "exited with status 0";
// balloon_grasp's grasp (1.5 s), the force envelope's first seconds (from 6 s) and the lift (7 s).
constexpr const char* kFirstTenSeconds = "--duration-s 10";

std::string Bin(const std::string& name) { return ::hilrig::test_support::BinDir() + "/" + name; }

std::string Scene(const std::string& name) {
  return ::hilrig::test_support::SourceDir() + "/scenarios/" + name + ".textproto";
}

// What one direction of the link carried and what the null modem did to it.
struct Injected {
  std::uint64_t bytes = 0;
  std::uint64_t dropped = 0;
  std::uint64_t flipped = 0;
  std::uint64_t inserted = 0;
  std::uint64_t faults() const { return dropped + flipped + inserted; }
};

// The null modem between the two sides; `faults` are its options. Stop() ends it and reads what
// it counted.
class NullModem {
 public:
  NullModem(const fs::path& dir, const std::string& faults) : out_(dir / "null_modem.out") {
    child_.emplace(StartShellCommand(Bin("pty_null_modem") + " " + faults + " >" + out_.string()));
    ready_ = WaitUntil([&] { return Has("ready\n"); }, kStartBoundS);
    std::istringstream lines(ReadFile(out_));
    std::string name, path;
    while (lines >> name && name != "ready" && lines >> path) paths_[name] = path;
  }
  bool ready() const { return ready_; }
  bool Has(const std::string& text) const { return ReadFile(out_).find(text) != std::string::npos; }
  const std::string& path(const std::string& side) { return paths_[side]; }

  std::map<std::string, Injected> Stop() {
    EXPECT_EQ(child_->Terminate(), kExitedOk);
    std::map<std::string, Injected> counts;
    std::istringstream lines(ReadFile(out_));
    std::string line;
    while (std::getline(lines, line)) {
      Injected injected;
      char name[32] = {};
      if (std::sscanf(line.c_str(),
                      "%31s bytes=%" SCNu64 " dropped=%" SCNu64 " flipped=%" SCNu64
                      " inserted=%" SCNu64,
                      name, &injected.bytes, &injected.dropped, &injected.flipped,
                      &injected.inserted) == 5) {
        counts[name] = injected;
      }
    }
    return counts;
  }

 private:
  fs::path out_;
  std::optional<ChildProcess> child_;
  bool ready_ = false;
  std::map<std::string, std::string> paths_;
};

// A finished `hilrig run`: how the process ended, what it said, and the report it wrote.
struct RunResult {
  std::optional<std::string> exit;  // nullopt: it ran into the bound and was killed
  std::string err;
  proto::Report report;
  fs::path out;
  double wall_s = 0;

  double Metric(const std::string& name) const {
    for (const proto::Metric& metric : report.metrics()) {
      if (metric.name() == name) return metric.value();
    }
    ADD_FAILURE() << "no metric " << name;
    return -1;
  }
};

// `scene` into `out` with the DUT `dut` and more `options` (--duration-s S cuts it).
ChildProcess StartSceneRun(const std::string& scene, const fs::path& out, const std::string& dut,
                           const std::string& options) {
  fs::create_directories(out);
  return StartShellCommand(HilrigBinary() + " run " + Scene(scene) + " --no-reference --out " +
                           out.string() + " --dut " + dut + " " + options + " >" +
                           (out / "stdout.txt").string() + " 2>" + (out / "stderr.txt").string());
}

RunResult FinishRun(ChildProcess& child, const fs::path& out, double bound_s = kRunBoundS) {
  const rig::SteadyClock clock;
  const std::int64_t start_ns = clock.NowNs();
  RunResult run;
  run.out = out;
  run.exit = WaitForExit(child, bound_s);
  if (!run.exit)
    ADD_FAILURE() << "hilrig run still running after " << bound_s << " s: " << child.Terminate();
  run.wall_s = double(clock.NowNs() - start_ns) * 1e-9;
  run.err = ReadFile(out / "stderr.txt");
  EXPECT_TRUE(
      google::protobuf::util::JsonStringToMessage(ReadFile(out / "report.json"), &run.report).ok())
      << out;
  return run;
}

ChildProcess StartRun(const fs::path& out, const std::string& dut,
                      const std::string& options = "") {
  return StartSceneRun("balloon_grasp", out, dut, options);
}

// The DUT side: dut_emu on the null modem's DUT ends of both lines.
ChildProcess StartDutEmu(NullModem& modem, const fs::path& dir) {
  return StartShellCommand(Bin("dut_emu") + " --serial " + modem.path("link_dut") + ",bridge=" +
                           modem.path("bridge_dut") + " 2>" + (dir / "dut_emu.err").string());
}

std::string SerialDut(NullModem& modem) {
  return "serial:" + modem.path("link_host") + ",bridge=" + modem.path("bridge_host");
}

// Runs balloon_grasp with `options` against dut_emu through a null modem with `faults`; returns
// the run and what the null modem injected.
std::pair<RunResult, std::map<std::string, Injected>> RunOverNullModem(
    const fs::path& dir, const std::string& faults, const std::string& options = "") {
  fs::create_directories(dir);
  NullModem modem(dir, faults);
  EXPECT_TRUE(modem.ready()) << ReadFile(dir / "null_modem.out");
  ChildProcess dut = StartDutEmu(modem, dir);
  ChildProcess hilrig = StartRun(dir / "out", SerialDut(modem), options);
  RunResult run = FinishRun(hilrig, dir / "out");
  dut.Terminate();
  return {std::move(run), modem.Stop()};
}

// The trace as columns of numbers by header name.
std::map<std::string, std::vector<double>> ReadTrace(const fs::path& file) {
  std::istringstream lines(ReadFile(file));
  std::string line;
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> columns;
  if (std::getline(lines, line)) {
    std::istringstream header(line);
    for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  }
  while (std::getline(lines, line)) {
    std::istringstream row(line);
    std::string cell;
    for (std::size_t i = 0; i < names.size() && std::getline(row, cell, ','); ++i) {
      columns[names[i]].push_back(std::strtod(cell.c_str(), nullptr));
    }
  }
  return columns;
}

// The largest difference between two traces' column `name`.
double MaxDifference(const std::map<std::string, std::vector<double>>& a,
                     const std::map<std::string, std::vector<double>>& b, const std::string& name) {
  if (!a.contains(name) || !b.contains(name)) {
    ADD_FAILURE() << "no column " << name;
    return INFINITY;
  }
  const auto& x = a.at(name);
  const auto& y = b.at(name);
  EXPECT_EQ(x.size(), y.size()) << name;
  double worst = 0;
  for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
    worst = std::max(worst, std::abs(x[i] - y[i]));
  }
  return worst;
}

void ExpectCompleteFolder(const RunResult& run) {
  for (const char* file : {"report.json", "trace.csv", "can.log", "junit.xml"}) {
    EXPECT_TRUE(fs::exists(run.out / file)) << run.out / file;
  }
  EXPECT_NE(run.report.stop_kind(), proto::STOP_INCOMPLETE) << run.err;
  EXPECT_GT(run.report.simulated_s(), 0);
}

// Completed with every envelope met. dut_emu measures no work per step and gives no core clock,
// so the scene's target envelope is not evaluated and the run exits 0.
void ExpectPassed(const RunResult& run) {
  EXPECT_EQ(run.report.stop_kind(), proto::STOP_COMPLETED) << run.report.stop_detail();
  EXPECT_GT(run.report.envelopes_size(), 0);
  for (const proto::EnvelopeResult& envelope : run.report.envelopes()) {
    EXPECT_TRUE(envelope.meets_expectation()) << envelope.name();
  }
  EXPECT_EQ(run.report.target().steps_measured(), 0u);
  for (const proto::TimingCheckResult& check : run.report.target_checks()) {
    EXPECT_FALSE(check.evaluated()) << check.name();
  }
  EXPECT_EQ(run.exit, kExitedOk) << run.err;
}

// The float firmware behind the line against the host's double build of the same controller:
// the largest difference per column the float arithmetic may make over a scene (five to ten times
// what balloon_grasp showed; load_n peaks as the balloon leaves its stand).
struct Tolerance {
  const char* column;
  double limit;
};
constexpr Tolerance kFloatTolerances[] = {
    {"z_m", 2e-4},
    {"position_error_m", 2e-4},
    {"tilt_deg", 0.02},
    {"thrust0_n", 0.01},
    {"grasp_force_n", 5e-4},
    {"grasp_force_estimate_n", 0.01},
    {"servo_angle_rad", 1e-5},
    {"load_n", 0.1},
};

// `serial` against the same run (`options`) with the controller in single precision in process.
void ExpectCloseToTheHostDut(const RunResult& serial, const fs::path& dir,
                             const std::string& options = "") {
  ChildProcess host = StartRun(dir, "inproc-float", options);
  const RunResult inproc = FinishRun(host, dir);
  EXPECT_EQ(inproc.report.stop_kind(), proto::STOP_COMPLETED) << inproc.err;
  const auto a = ReadTrace(serial.out / "trace.csv");
  const auto b = ReadTrace(inproc.out / "trace.csv");
  for (const Tolerance& tolerance : kFloatTolerances) {
    const double difference = MaxDifference(a, b, tolerance.column);
    std::cout << tolerance.column << " max difference " << difference << "\n";
    EXPECT_LE(difference, tolerance.limit) << tolerance.column;
  }
}

// Frames a side counted as damaged: a bad checksum, bad COBS, too long.
double BadFrames(const RunResult& run, const std::string& prefix) {
  return run.Metric(prefix + "bad_checksum") + run.Metric(prefix + "malformed") +
         run.Metric(prefix + "oversize");
}

TEST(SerialLineTest, BalloonGraspOverANullModemPassesCloseToTheHostDut) {
  const fs::path dir = FreshTestDir("serial_clean");
  const auto [serial, injected] = RunOverNullModem(dir / "serial", "");
  ExpectPassed(serial);
  EXPECT_EQ(serial.Metric("line_commands_received"), 34000);
  EXPECT_EQ(serial.Metric("dut_line_bad_checksum") + serial.Metric("line_bad_checksum"), 0);
  EXPECT_EQ(injected.at("link_to_dut").faults() + injected.at("link_to_host").faults(), 0u);
  std::cout << "balloon_grasp over the null modem: real-time factor "
            << serial.report.real_time_factor() << ", " << serial.wall_s << " s\n";

  ExpectCloseToTheHostDut(serial, dir / "host");
}

// A few damaged bytes both ways: each costs the frame it hit and a retry of the step, never the
// run, and the trace stays as close to the host's DUT as on a clean line.
TEST(SerialLineTest, RidesThroughAFewDroppedFlippedAndInsertedBytes) {
  const fs::path dir = FreshTestDir("serial_faults");
  const auto [run, injected] = RunOverNullModem(
      dir / "serial", "--seed 7 --drop 1e-5 --flip 1e-5 --insert 1e-5", kFirstTenSeconds);
  ExpectPassed(run);
  const Injected to_dut = injected.at("link_to_dut");
  const Injected to_host = injected.at("link_to_host");
  const double lost = run.Metric("line_step_retries") - run.Metric("line_stale_answers");
  std::cout << "injected to the dut " << to_dut.dropped << " dropped, " << to_dut.flipped
            << " flipped, " << to_dut.inserted << " inserted; to the host " << to_host.dropped
            << " dropped, " << to_host.flipped << " flipped, " << to_host.inserted
            << " inserted\ncounted bad frames: dut " << BadFrames(run, "dut_line_") << ", host "
            << BadFrames(run, "line_") << "; step retries " << run.Metric("line_step_retries")
            << ", stale answers " << run.Metric("line_stale_answers") << ", hellos "
            << run.Metric("line_hellos_sent") << ", configs " << run.Metric("line_configs_sent")
            << "\n";
  ASSERT_GT(to_dut.faults(), 0u);
  ASSERT_GT(to_host.faults(), 0u);
  // A fault damages the frame it hits; a zero byte inserted or flipped in splits it in two.
  EXPECT_GE(BadFrames(run, "dut_line_"), 1);
  EXPECT_LE(BadFrames(run, "dut_line_"), 2.0 * double(to_dut.faults()));
  EXPECT_GE(BadFrames(run, "line_"), 1);
  EXPECT_LE(BadFrames(run, "line_"), 2.0 * double(to_host.faults()));
  // Every lost step or command is one retry; a retry whose first answer came after all leaves a
  // stale twin, which is no loss. One fault loses at most two messages: a dropped or flipped 0x00
  // delimiter joins the two frames it separated into one bad frame.
  EXPECT_GE(lost, 1);
  EXPECT_LE(lost, 2.0 * double(to_dut.faults() + to_host.faults()));
  ExpectCloseToTheHostDut(run, dir / "host", kFirstTenSeconds);
}

// Every twentieth byte damaged, from a second into the run: no step gets through any more, and
// the watchdog stops the run by name within its timeout, with the report folder complete.
TEST(SerialLineTest, StopsByNameWhenTheLineIsTooDamagedToCarrySteps) {
  const fs::path dir = FreshTestDir("serial_heavy");
  const auto [run, injected] = RunOverNullModem(
      dir / "serial", "--seed 3 --from-byte 50000 --drop 0.02 --flip 0.02 --insert 0.01");
  std::cout << "stopped after " << run.wall_s << " s at " << run.report.simulated_s()
            << " s: " << run.report.stop_reason() << "\n";
  EXPECT_EQ(run.exit, "exited with status 1") << run.err;
  EXPECT_EQ(run.report.stop_kind(), proto::STOP_DUT_FAILED) << run.report.stop_reason();
  EXPECT_NE(run.report.stop_detail().find("did not answer"), std::string::npos)
      << run.report.stop_detail();
  ExpectCompleteFolder(run);
  EXPECT_LT(run.wall_s, 10);  // the watchdog's second, the start and the report
  EXPECT_LT(run.report.simulated_s(), 10);
  EXPECT_EQ(run.Metric("line_watchdog_timeouts"), 1);
  EXPECT_GT(run.Metric("line_step_retries"), 1);
  // The direction whose stream reaches the offset first (the commands') stalls the run.
  EXPECT_GT(injected.at("link_to_dut").faults() + injected.at("link_to_host").faults(), 20u);
}

// The DUT process killed in the middle of a run: its line goes silent, and the run stops by name
// within the answer timeout of the kill, with the report folder complete.
TEST(SerialLineTest, StopsByNameWithinASecondWhenTheDutIsKilled) {
  const fs::path dir = FreshTestDir("serial_killed");
  NullModem modem(dir, "--mark-at 400000");  // about 8 s into the scene
  ASSERT_TRUE(modem.ready());
  ChildProcess dut = StartDutEmu(modem, dir);
  ChildProcess hilrig = StartRun(dir / "out", SerialDut(modem), "--dut-timeout-s 0.5");
  ASSERT_TRUE(WaitUntil([&] { return modem.Has("mark\n"); }, kRunBoundS));
  const rig::SteadyClock clock;
  const std::int64_t killed_ns = clock.NowNs();
  ASSERT_EQ(::kill(dut.pid(), SIGKILL), 0);
  const RunResult run = FinishRun(hilrig, dir / "out", 10);
  const double after_kill_s = double(clock.NowNs() - killed_ns) * 1e-9;
  std::cout << "stopped " << after_kill_s << " s after the kill, at " << run.report.simulated_s()
            << " s: " << run.report.stop_reason() << "\n";
  EXPECT_LT(after_kill_s, 1.0);
  EXPECT_EQ(run.exit, "exited with status 1") << run.err;
  EXPECT_EQ(run.report.stop_kind(), proto::STOP_DUT_FAILED) << run.report.stop_reason();
  ExpectCompleteFolder(run);
  EXPECT_GT(run.report.simulated_s(), 5);
  EXPECT_LT(run.report.simulated_s(), 34);
  EXPECT_EQ(dut.PollExit(), "killed by signal 9");
  modem.Stop();
}

// MAVLink HITL without a board: PX4's stand-in on a pseudo-terminal the rig opens, both links on
// the one line, the rig in real time answering each tick with the board's latest outputs.
TEST(MavlinkHitlTest, AStandInBoardFliesHoverInRealTime) {
  const fs::path out = FreshTestDir("mavlink_hitl_hover");
  ChildProcess run = StartSceneRun("hover", out, "mavlink-emu-hitl", "--realtime --duration-s 3");
  const RunResult result = FinishRun(run, out);
  ExpectCompleteFolder(result);
  EXPECT_EQ(result.report.stop_kind(), proto::STOP_COMPLETED) << result.report.stop_detail();
  EXPECT_EQ(result.Metric("mavlink_sensor_steps"), 749);  // 4 ms to 2.996 s
  EXPECT_GE(result.Metric("mavlink_controls_received"), 700) << "about one per sensor step";
  EXPECT_GT(result.Metric("mavlink_gps_sent"), 25);
  // The envelopes whose windows the first 3 s reach.
  int checked = 0;
  for (const proto::EnvelopeResult& envelope : result.report.envelopes()) {
    if (envelope.name() != "takeoff_position_error" && envelope.name() != "tilt") continue;
    EXPECT_TRUE(envelope.meets_expectation()) << envelope.name();
    ++checked;
  }
  EXPECT_EQ(checked, 2);
  EXPECT_TRUE(fs::exists(out / "mavlink.tlog"));
}

// A board that says it is there and then answers nothing: the run stops by name once the first
// sensor step has gone unanswered for 5 s, with its folder complete.
TEST(MavlinkHitlTest, ASilentBoardIsNamedWithinItsTimeout) {
  const fs::path out = FreshTestDir("mavlink_hitl_silent");
  dut_fw::Pty board = dut_fw::OpenPty();
  std::array<std::uint8_t, mavlink::kMaxFrameBytes> frame;
  const std::size_t size = mavlink::EncodeMessage(mavlink::Heartbeat{}, 0, 1, 1, frame);
  ASSERT_EQ(::write(board.master.get(), frame.data(), size), ssize_t(size));
  // The board reads what the rig sends and throws it away, so the rig's writes never block.
  std::atomic<bool> done = false;
  std::thread drain([&] {
    std::array<char, 4096> bytes;
    while (!done) {
      pollfd in{board.master.get(), POLLIN, 0};
      if (::poll(&in, 1, 50) > 0) (void)!::read(board.master.get(), bytes.data(), bytes.size());
    }
  });
  ChildProcess run =
      StartSceneRun("hover", out, "px4-hitl:" + board.slave_path, "--realtime --duration-s 20");
  const RunResult result = FinishRun(run, out, 30);
  done = true;
  drain.join();
  ExpectCompleteFolder(result);
  EXPECT_EQ(result.report.stop_kind(), proto::STOP_DUT_FAILED) << result.report.stop_reason();
  EXPECT_THAT(result.report.stop_reason(),
              ::testing::HasSubstr("the board sent no HIL_ACTUATOR_CONTROLS for 5 s after the "
                                   "first sensor step"));
  EXPECT_LT(result.wall_s, 15);
}

}  // namespace
}  // namespace hilrig::host
