// A DUT command with a NaN or infinite thrust or servo angle is a DUT fault: refused, counted,
// named in the report, and the run fails (or stops where the scene says so). A scene that stays
// on the ground cannot pass on a DUT that answers every tick with NaN.
#include "host/runner/dut_faults.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "host/report/report_files.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(NonFiniteCommandFieldTest, NamesTheFirstThrustOrServoAngleThatIsNotFinite) {
  ActuatorMessage command;
  EXPECT_EQ(NonFiniteCommandField(command), std::nullopt);
  command.estimated_position_m.x() = kNaN;  // telemetry: not a command
  EXPECT_EQ(NonFiniteCommandField(command), std::nullopt);
  command.servo_angle_rad = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(NonFiniteCommandField(command), "servo_angle_rad = -inf");
  command.rotor_thrust_n[2] = kNaN;
  EXPECT_EQ(NonFiniteCommandField(command), "rotor_thrust_n[2] = nan");
}

// Answers every control tick with NaN on every rotor, armed.
class NaNThrustDut final : public DutPort {
 public:
  void Send(const DutInput&) override {}
  rig::Result<ActuatorMessage> Step(std::uint64_t, std::int64_t) override {
    ActuatorMessage command;
    command.armed = true;
    command.rotor_thrust_n.fill(kNaN);
    return command;
  }
  DutCounters counters() const override { return {}; }
  std::string description() const override { return "NaN thrust"; }
};

proto::Report RunGroundedSceneWithNaNThrust(const std::string& extra_simulation) {
  const auto spec = ParseScenario(R"(name: "grounded"
simulation { duration_s: 1 control_rate_hz: 100 )" +
                                      extra_simulation + R"( }
envelopes { name: "on_the_ground" signal: ALTITUDE_M upper: 0.01 }
)",
                                  "grounded.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  const ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);
  const rig::SimClock wall_clock;
  RunControl control{.wall_clock = &wall_clock};
  control.dut_factory = [](const ScenarioConfig&, std::unique_ptr<rig::CanBus>,
                           double) -> rig::Result<std::unique_ptr<DutPort>> {
    return std::unique_ptr<DutPort>(std::make_unique<NaNThrustDut>());
  };
  return RunScenario(config, {}, control);
}

TEST(DutFaultTest, NaNThrustOnAGroundedSceneFailsTheRunWithTheFaultNamed) {
  const proto::Report report = RunGroundedSceneWithNaNThrust("");
  EXPECT_EQ(report.stop_kind(), proto::STOP_COMPLETED);
  ASSERT_EQ(report.envelopes_size(), 1);
  EXPECT_TRUE(report.envelopes(0).meets_expectation());  // it did stay on the ground
  EXPECT_FALSE(report.passed());
  ASSERT_TRUE(report.has_dut_faults());
  EXPECT_EQ(report.dut_faults().non_finite_commands(), 100u);  // every control tick of 1 s
  EXPECT_EQ(report.dut_faults().first_at_s(), 0);
  EXPECT_EQ(report.dut_faults().first_field(), "rotor_thrust_n[0] = nan");
  EXPECT_EQ(FormatDutFaultLine(report.dut_faults()),
            "DUT FAULT  100 non-finite commands refused, the first at 0 s (rotor_thrust_n[0] = "
            "nan): the run fails");
}

TEST(DutFaultTest, ASceneThatSaysSoStopsAtTheFirstFault) {
  const proto::Report report = RunGroundedSceneWithNaNThrust("dut_fault: DUT_FAULT_STOP");
  EXPECT_EQ(report.stop_kind(), proto::STOP_DUT_FAULT);
  EXPECT_EQ(report.stop_reason(), "dut fault: non-finite command rotor_thrust_n[0] = nan at 0 s");
  EXPECT_EQ(report.ticks(), 0u);
  EXPECT_EQ(report.dut_faults().non_finite_commands(), 1u);
  EXPECT_FALSE(report.passed());
}

}  // namespace
}  // namespace hilrig::host
