// The S(B) hard cases met inside a flight: a stray field saturates a pad's chip, then the reference
// magnetometer's, while the vehicle holds a container by its tactile force loops. The DUT must flag
// every sample it cannot decode, keep NaN out of everything, hold its grasp instead of winding up
// on a force it cannot see, and keep the object and the vehicle where they were.
#include <gtest/gtest.h>

#include <sstream>

#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"

namespace hilrig::host {
namespace {

constexpr const char* kHeldContainer = R"(name: "hard_cases"
vehicle { initial_position_m { z: 0.5 } }
models { tactile { enabled: true field_fidelity: "map:8" zeroing_s: 1 } }
object { fixture: "bead_container" }
simulation { duration_s: 12 }
timeline { at_s: 1.5 grasp { force_n: 3 } }
timeline { at_s: 5 remove_support { } }
envelopes { name: "altitude" signal: ALTITUDE_ERROR_M upper: 0.1 }
envelopes { name: "dropped" signal: OBJECT_DROPPED upper: 0 }
envelopes { name: "damaged" signal: OBJECT_DAMAGED upper: 0 }
envelopes { name: "force" signal: GRASP_FORCE_N lower: 1.5 upper: 4.5 from_s: 6 }
)";

double Metric(const proto::Report& report, const std::string& name) {
  for (const auto& metric : report.metrics()) {
    if (metric.name() == name) return metric.value();
  }
  ADD_FAILURE() << "no metric " << name;
  return -1;
}

proto::Report RunWith(const std::string& timeline, std::string* trace_out) {
  const auto spec = ParseScenario(std::string(kHeldContainer) + timeline, "hard.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);
  EXPECT_TRUE(LoadTactileCalibration(config).ok());
  std::ostringstream trace;
  const rig::SimClock wall_clock;
  const proto::Report report =
      RunScenario(config, {.trace_csv = &trace}, {.wall_clock = &wall_clock});
  *trace_out = trace.str();
  return report;
}

void ExpectFlightUnharmed(const proto::Report& report, const std::string& trace) {
  EXPECT_EQ(report.stop_reason(), "completed");
  EXPECT_EQ(Metric(report, "non_finite_trace_samples"), 0);
  EXPECT_EQ(trace.find("nan"), std::string::npos);
  for (const auto& envelope : report.envelopes()) {
    EXPECT_EQ(envelope.verdict(), proto::PASS)
        << envelope.name() << " worst " << envelope.worst_value() << " at "
        << envelope.worst_at_s();
  }
}

TEST(TactileHardCasesTest, SaturatedPadIsFlaggedAndTheFlightCarriesOn) {
  std::string trace;
  // 0.2 T along the chip's z: far beyond the MLX90393's range at this gain.
  const proto::Report report = RunWith(
      "timeline { at_s: 7 stray_field { node: 3 field_sensor_t { z: 0.2 } duration_s: 0.5 } }\n",
      &trace);
  // 25 samples at 50 Hz, every one flagged.
  EXPECT_GE(Metric(report, "dut_tactile_samples_flagged"), 24 + 6);
  ExpectFlightUnharmed(report, trace);
}

TEST(TactileHardCasesTest, SaturatedReferenceFlagsEveryPadAndTheFlightCarriesOn) {
  std::string trace;
  const proto::Report report = RunWith(
      "timeline { at_s: 7 stray_field { node: 7 field_sensor_t { x: 0.2 } duration_s: 0.2 } }\n",
      &trace);
  // Ten reference samples saturated: the six pads' samples compensated against them are flagged.
  EXPECT_GE(Metric(report, "dut_tactile_samples_flagged"), 6 * 9 + 6);
  ExpectFlightUnharmed(report, trace);
}

TEST(TactileHardCasesTest, WithoutStrayFieldsNothingIsFlagged) {
  std::string trace;
  const proto::Report report = RunWith("", &trace);
  // Only start-up: each pad's first sample can beat the first reference sample to the DUT.
  EXPECT_LE(Metric(report, "dut_tactile_samples_flagged"), 6);
  ExpectFlightUnharmed(report, trace);
}

}  // namespace
}  // namespace hilrig::host
