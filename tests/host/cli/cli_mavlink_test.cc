// `hilrig run --dut mavlink-emu`: scenes flown through PX4's stand-in over MAVLink (a grasping one
// among them), their telemetry log in the run folder, and the modes the link refuses by name. The
// link itself is tested in tests/host/linked_dut/, the stand-in in tests/dut_emu/.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <vector>

#include "host/cli/cli.h"
#include "host/link/mavlink_hil.h"
#include "host/mavlink/tlog.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

std::string Scenario(const char* name) {
  return ::hilrig::test_support::SourceDir() + "/scenarios/" + name + ".textproto";
}

TEST(CliMavlinkTest, HoverFliesOverMavlinkAndLeavesItsTelemetryLog) {
  const std::filesystem::path out = FreshTestDir("cli_mavlink_hover");
  const CliResult run = Cli(
      {"run", Scenario("hover"), "--no-reference", "--out", out.string(), "--dut", "mavlink-emu"});
  EXPECT_EQ(run.exit_code, kExitPass) << run.err << run.out;
  const std::string log = ReadFile(out / "mavlink.tlog");
  const std::vector<std::uint8_t> bytes(log.begin(), log.end());
  const mavlink::TlogContents contents = mavlink::ReadTlog(bytes);
  EXPECT_EQ(contents.bytes_skipped, 0u);
  // Each 4 ms sensor step is one HIL_SENSOR and its HIL_ACTUATOR_CONTROLS, over the 40 s scene.
  std::size_t sensors = 0, controls = 0;
  for (const mavlink::TlogRecord& record : contents.records) {
    sensors += record.frame.message_id == mavlink::HilSensor::kId;
    controls += record.frame.message_id == mavlink::HilActuatorControls::kId;
  }
  EXPECT_EQ(sensors, 9999u);  // 4 ms to 39.996 s: the first step comes after time 0
  EXPECT_EQ(controls, sensors);
  EXPECT_NE(ReadFile(out / "report.json").find("\"mavlink_sensor_steps\""), std::string::npos);
}

// PX4 marks a sensor stale when its readings repeat exactly, so a scene without IMU noise cannot
// fly over MAVLink: the stand-in stops and the run says why.
TEST(CliMavlinkTest, AnImuWithoutNoiseIsStaleAndTheRunSaysSo) {
  const std::filesystem::path dir = FreshTestDir("cli_mavlink_stale");
  std::string spec = ReadFile(Scenario("hover"));
  spec.replace(spec.find("models {"), 8, "models {\n  noise: NOISE_OFF");
  std::ofstream(dir / "quiet.textproto") << spec;
  const CliResult run = Cli({"run", (dir / "quiet.textproto").string(), "--no-reference", "--out",
                             (dir / "out").string(), "--dut", "mavlink-emu"});
  EXPECT_EQ(run.exit_code, kExitCheckFailed);
  EXPECT_NE(ReadFile(dir / "out" / "report.json").find("found its IMU readings stale"),
            std::string::npos)
      << run.out;
}

// The grasp travels as MAV_CMD_DO_GRIPPER, the tactile frames as CAN_FRAME and the DUT's
// estimates back as DEBUG_FLOAT_ARRAY: load_ramp holds its container and checks the estimate.
TEST(CliMavlinkTest, LoadRampGraspsOverMavlinkWithTheTactileFramesAndEstimates) {
  const std::filesystem::path out = FreshTestDir("cli_mavlink_grasp");
  const CliResult run = Cli({"run", Scenario("load_ramp"), "--no-reference", "--out", out.string(),
                             "--dut", "mavlink-emu"});
  EXPECT_EQ(run.exit_code, kExitPass) << run.err << run.out;
  EXPECT_NE(run.out.find("undamaged, held"), std::string::npos) << run.out;
  const std::string log = ReadFile(out / "mavlink.tlog");
  const mavlink::TlogContents contents =
      mavlink::ReadTlog(std::vector<std::uint8_t>(log.begin(), log.end()));
  std::size_t can_frames = 0, estimates = 0, gripper_commands = 0;
  for (const mavlink::TlogRecord& record : contents.records) {
    const std::optional<mavlink::AnyMessage> message = mavlink::DecodeMessage(record.frame);
    ASSERT_TRUE(message.has_value());
    can_frames += std::holds_alternative<mavlink::CanFrame>(*message);
    estimates += std::holds_alternative<mavlink::DebugFloatArray>(*message);
    const auto* command = std::get_if<mavlink::CommandLong>(&*message);
    gripper_commands += command != nullptr && command->command == kMavCmdDoGripper;
  }
  EXPECT_GT(can_frames, 1000u);
  EXPECT_EQ(estimates, 11249u) << "one per sensor step over 45 s";
  EXPECT_EQ(gripper_commands, 1u) << "sent once, accepted at once";
}

TEST(CliMavlinkTest, RealTimeAndLinkOptionsAreRefused) {
  CliResult run = Cli({"run", Scenario("hover"), "--dut", "mavlink-emu", "--realtime"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("runs in lockstep only"), std::string::npos) << run.err;
  run = Cli({"run", Scenario("hover"), "--dut", "mavlink-emu", "--dut-link", "tcp"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  run = Cli({"run", Scenario("hover"), "--dut", "mavlink-emu", "--dut-timeout-s", "-1"});
  EXPECT_EQ(run.exit_code, kExitBadInput);
  EXPECT_NE(run.err.find("--dut-timeout-s: "), std::string::npos) << run.err;
}

}  // namespace
}  // namespace hilrig::host
