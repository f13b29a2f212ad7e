// The DUT firmware built in float, as the target builds it, against the double build over a whole
// shipped scenario: both must meet the scenario's envelopes, and the float build's traces must stay
// close to the double build's (single precision costs resolution, not behaviour).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "host/dut/firmware_config.h"
#include "host/dut/in_process_dut.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"
#include "host/trace/trace_sample.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

// The compared signals of every trace sample.
struct RunTrace {
  std::vector<double> grasp_force_n, altitude_error_m, horizontal_error_m;
};

struct RunResult {
  proto::Report report;
  RunTrace trace;
};

RunResult RunWith(const ScenarioConfig& config, DutFactory factory) {
  RunResult run;
  std::ostringstream trace_csv;
  const rig::SimClock wall_clock;
  RunControl control{.wall_clock = &wall_clock};
  control.dut_factory = std::move(factory);
  const auto keep = [&run](const TraceSample& sample) {
    run.trace.grasp_force_n.push_back(sample.grasp_force_n);
    run.trace.altitude_error_m.push_back(SignalValue(sample, proto::ALTITUDE_ERROR_M));
    run.trace.horizontal_error_m.push_back(SignalValue(sample, proto::HORIZONTAL_ERROR_M));
  };
  run.report = RunScenario(config, {&trace_csv, nullptr, nullptr, keep}, control);
  return run;
}

double MaxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    worst = std::max(worst, std::abs(a[i] - b[i]));
  }
  return worst;
}

TEST(FloatDutTest, BalloonGraspInFloatMeetsTheEnvelopesAndTracksTheDoubleBuild) {
  auto spec =
      LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/balloon_grasp.textproto");
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  spec.value().mutable_models()->mutable_tactile()->set_field_fidelity("map:8");
  ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);
  ASSERT_TRUE(LoadTactileCalibration(config).ok());

  const RunResult double_run = RunWith(config, nullptr);
  const RunResult float_run =
      RunWith(config,
              [](const ScenarioConfig& scene, std::unique_ptr<rig::CanBus> bus,
                 double period_s) -> rig::Result<std::unique_ptr<DutPort>> {
                return std::unique_ptr<DutPort>(std::make_unique<SinglePrecisionInProcessDut>(
                    FirmwareFor<float>(scene), std::move(bus), period_s));
              });

  EXPECT_TRUE(double_run.report.passed());
  EXPECT_TRUE(float_run.report.passed()) << float_run.report.stop_reason();
  EXPECT_EQ(float_run.report.stop_reason(), "completed");
  bool names_float = false;
  for (const auto& model : float_run.report.models()) {
    names_float = names_float || model.fidelity() == "in-process dut_fw (float)";
  }
  EXPECT_TRUE(names_float);
  ASSERT_EQ(double_run.trace.grasp_force_n.size(), float_run.trace.grasp_force_n.size());
  // The runs differ only in the DUT's rounding, so they must not drift apart.
  EXPECT_LT(MaxDifference(double_run.trace.grasp_force_n, float_run.trace.grasp_force_n), 0.03);
  EXPECT_LT(MaxDifference(double_run.trace.altitude_error_m, float_run.trace.altitude_error_m),
            0.005);
  EXPECT_LT(MaxDifference(double_run.trace.horizontal_error_m, float_run.trace.horizontal_error_m),
            0.005);
}

}  // namespace
}  // namespace hilrig::host
