// Grasp scenes end to end through the runner: the pads' forces go through the sensor forward
// model and the CAN bus to the DUT, whose servo command closes the frame on the object. These
// tests use a cheap field map and share one calibration, so each run costs well under a second.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/scenario/scenario_validation.h"
#include "host/setup/scene_setup.h"

namespace hilrig::host {
namespace {

std::string GraspSpec(const std::string& object, double force_n, const std::string& extra = "") {
  return R"(name: "grasp"
vehicle { initial_position_m { z: 0.5 } }
models { tactile { enabled: true field_fidelity: "map:8" zeroing_s: 1 } }
object { )" +
         object +
         R"( }
simulation { duration_s: 12 }
timeline { at_s: 1.5 grasp { force_n: )" +
         std::to_string(force_n) + R"( } }
envelopes { name: "force" signal: GRASP_FORCE_N lower: 0.25 upper: 0.65 from_s: 6 }
envelopes { name: "damage" signal: OBJECT_DAMAGED upper: 0 }
)" + extra;
}

// One calibration for every test: the jigs are the same, only the object changes.
const proto::Calibration& SharedCalibration() {
  static const proto::Calibration calibration = [] {
    const auto spec = ParseScenario(GraspSpec(R"(fixture: "balloon")", 0.6), "grasp.textproto");
    ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);
    EXPECT_TRUE(LoadTactileCalibration(config).ok());
    return *config.hall_sensors.calibration;
  }();
  return calibration;
}

proto::Report RunGrasp(const std::string& text, std::string* trace_out = nullptr) {
  const auto spec = ParseScenario(text, "grasp.textproto");
  EXPECT_TRUE(spec.ok()) << (spec.ok() ? "" : spec.error().message);
  EXPECT_TRUE(ValidateScenario(spec.value()).empty());
  ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);
  config.hall_sensors.calibration = SharedCalibration();
  std::ostringstream trace;
  const rig::SimClock wall_clock;
  const proto::Report report =
      RunScenario(config, {.trace_csv = &trace}, {.wall_clock = &wall_clock});
  if (trace_out != nullptr) *trace_out = trace.str();
  return report;
}

double Metric(const proto::Report& report, const std::string& name) {
  for (const auto& metric : report.metrics()) {
    if (metric.name() == name) return metric.value();
  }
  ADD_FAILURE() << "no metric " << name;
  return std::nan("");
}

const proto::EnvelopeResult& Envelope(const proto::Report& report, const std::string& name) {
  for (const auto& envelope : report.envelopes()) {
    if (envelope.name() == name) return envelope;
  }
  static const proto::EnvelopeResult kNone;
  ADD_FAILURE() << "no envelope " << name;
  return kNone;
}

TEST(GraspSceneTest, RegulatesTheBalloonThroughTheSensorsAndTheBus) {
  const proto::Report report = RunGrasp(GraspSpec(R"(fixture: "balloon")", 0.6));
  EXPECT_EQ(report.stop_reason(), "completed");
  EXPECT_EQ(Envelope(report, "force").verdict(), proto::PASS);
  EXPECT_EQ(Envelope(report, "damage").verdict(), proto::PASS);
  ASSERT_EQ(report.objects_size(), 1);
  EXPECT_EQ(report.objects(0).fixture(), "balloon");
  EXPECT_EQ(report.objects(0).damage(), "none");
  // Six pads share 0.6 N: a tenth of a newton each, far from the 0.45 N burst.
  EXPECT_NEAR(report.objects(0).peak_normal_force_n(), 0.1, 0.03);
  EXPECT_LT(Metric(report, "grasp_force_tracking_error_rms"), 0.03);
}

TEST(GraspSceneTest, OpenLoopClosingBurstsTheBalloon) {
  const proto::Report report = RunGrasp(
      GraspSpec(R"(fixture: "balloon")", 0.6, "grasp_controller { force_feedback: false }\n"));
  EXPECT_EQ(Envelope(report, "damage").verdict(), proto::FAIL);
  ASSERT_EQ(report.objects_size(), 1);
  EXPECT_EQ(report.objects(0).damage(), "burst");
  EXPECT_EQ(report.objects(0).final_state(), "destroyed");
}

// The acceptance sweep: 10x softer and 10x stiffer objects must integrate stably. Stable means
// no non-finite trace sample and the grasp's stored energy within what the servo can put in;
// whether the force envelope still holds is the report's to say, and it says it either way.
class StiffnessSweepTest
    : public ::testing::TestWithParam<std::tuple<const char*, double, double>> {};

TEST_P(StiffnessSweepTest, StaysStableAndReportsTheEnvelope) {
  const auto [fixture, scale, force_n] = GetParam();
  const std::string object =
      std::string("fixture: \"") + fixture + "\" stiffness_scale: " + std::to_string(scale);
  std::string trace;
  const proto::Report report = RunGrasp(GraspSpec(object, force_n), &trace);
  EXPECT_EQ(report.stop_reason(), "completed");
  EXPECT_EQ(Metric(report, "non_finite_trace_samples"), 0);
  EXPECT_LE(Metric(report, "grasp_elastic_energy_peak"),
            Metric(report, "grasp_elastic_energy_bound"));
  EXPECT_GT(Metric(report, "grasp_force_peak"), 0.0);
  EXPECT_EQ(trace.find("nan"), std::string::npos);
  EXPECT_GT(Envelope(report, "force").samples_checked(), 0u);
}

INSTANTIATE_TEST_SUITE_P(TenTimesEitherWay, StiffnessSweepTest,
                         ::testing::Values(std::make_tuple("balloon", 0.1, 0.6),
                                           std::make_tuple("balloon", 10.0, 0.6),
                                           std::make_tuple("glass_cup", 0.1, 0.6),
                                           std::make_tuple("glass_cup", 10.0, 0.6)));

TEST(GraspSceneTest, SidewaysShoveReleasesPadsAndTheReportCountsIt) {
  // The bottle held at 3.5 N (0.58 N per pad), the vehicle shoved sideways at about 20 m/s^2: the
  // pads on the far side would have to pull 0.18 kg x 20 m/s^2 / 3 = 1.2 N, so they let go and the
  // others carry the bottle. Regulated, the grasp never releases a pad.
  const std::string hand_over = "timeline { at_s: 5 remove_support {} }\n";
  const proto::Report shoved = RunGrasp(GraspSpec(R"(fixture: "water_bottle")", 3.5, hand_over + R"(
timeline { at_s: 8 disturbance { force_world_n { x: 15 } duration_s: 0.2 } }
)"));
  EXPECT_GT(Metric(shoved, "grasp_pad_release_ticks"), 0);
  EXPECT_LT(Metric(shoved, "grasp_unbalanced_horizontal_force_max"), 1e-9);
  const proto::Report calm = RunGrasp(GraspSpec(R"(fixture: "water_bottle")", 3.5, hand_over));
  EXPECT_EQ(Metric(calm, "grasp_pad_release_ticks"), 0);
}

TEST(GraspSceneTest, HandOverPutsTheBottlesWeightOnThePadsAndTheDutSeesIt) {
  const proto::Report report = RunGrasp(GraspSpec(R"(fixture: "water_bottle")", 3.5, R"(
timeline { at_s: 5 remove_support {} }
envelopes { name: "load" signal: LOAD_N lower: 1.70 upper: 1.85 from_s: 8 }
envelopes { name: "load_estimate" signal: LOAD_ESTIMATE_ERROR_N upper: 0.1 from_s: 8 }
envelopes { name: "altitude" signal: ALTITUDE_ERROR_M upper: 0.05 from_s: 8 }
)"));
  EXPECT_EQ(Envelope(report, "load").verdict(), proto::PASS)
      << Envelope(report, "load").worst_value();
  EXPECT_EQ(Envelope(report, "load_estimate").verdict(), proto::PASS)
      << Envelope(report, "load_estimate").worst_value();
  EXPECT_EQ(Envelope(report, "altitude").verdict(), proto::PASS)
      << Envelope(report, "altitude").worst_value();
  EXPECT_EQ(report.objects(0).final_state(), "held");
}

// The bottle on a stand 20 cm above the frame is beyond the pads' reach (55 mm half height plus
// the pads' 10 mm): the frame closes on nothing, and the hand-over drops the bottle instead of
// hanging it, off centre, on the pads.
TEST(GraspSceneTest, ABottleAboveThePadsIsNotGripped) {
  const proto::Report report =
      RunGrasp(GraspSpec(R"(fixture: "water_bottle" stand_height_m: 0.7)", 3.5, R"(
timeline { at_s: 5 remove_support {} }
envelopes { name: "nothing_gripped" signal: GRASP_FORCE_N upper: 0 }
envelopes { name: "no_load" signal: LOAD_N upper: 0.01 }
)"));
  EXPECT_EQ(Envelope(report, "nothing_gripped").verdict(), proto::PASS)
      << Envelope(report, "nothing_gripped").worst_value();
  EXPECT_EQ(Envelope(report, "no_load").verdict(), proto::PASS)
      << Envelope(report, "no_load").worst_value();
  EXPECT_EQ(report.objects(0).final_state(), "dropped");
}

// A gripped object still on its stand ties the vehicle to the world through the pads' shear
// stiffness (6 x 1.5 N/mm). Undamped and sampled once per tick, that spring and the DUT's load
// feedforward rang between the friction limits (-3 N .. +1.3 N); the pads' shear damping holds
// it to a slow wander.
TEST(GraspSceneTest, GrippingAnObjectOnItsStandDoesNotRing) {
  const proto::Report report = RunGrasp(GraspSpec(R"(fixture: "water_bottle")", 3.5, R"(
envelopes { name: "quiet" signal: LOAD_N lower: -0.5 upper: 0.5 from_s: 4 }
)"));
  EXPECT_EQ(Envelope(report, "quiet").verdict(), proto::PASS)
      << Envelope(report, "quiet").worst_value();
  EXPECT_EQ(report.objects(0).final_state(), "on_stand");
}

TEST(GraspSceneTest, WithoutTactileForceInThePositionLoopTheBottleSinksTheVehicle) {
  const proto::Report report = RunGrasp(GraspSpec(R"(fixture: "water_bottle")", 3.5, R"(
grasp_controller { external_force_in_position_loop: false }
timeline { at_s: 5 remove_support {} }
envelopes { name: "altitude" signal: ALTITUDE_ERROR_M upper: 0.05 from_s: 8 }
)"));
  const proto::EnvelopeResult& altitude = Envelope(report, "altitude");
  EXPECT_EQ(altitude.verdict(), proto::FAIL);
  // The PD alone needs m_bottle g / (m Kp) = 1.77 / (0.556 * 9) = 0.35 m of error.
  EXPECT_GT(altitude.worst_value(), 0.25);
}

TEST(GraspSceneTest, PouringIntoTheContainerRaisesTheLoadByTheMassPoured) {
  const proto::Report report = RunGrasp(GraspSpec(R"(fixture: "bead_container")", 4.0, R"(
timeline { at_s: 4 setpoint { position_m { z: 0.55 } transition_s: 1 } }
timeline { at_s: 6 pour { mass_kg: 0.1 duration_s: 2 } }
envelopes { name: "load_after" signal: LOAD_N lower: 1.5 upper: 1.65 from_s: 9.5 }
)"));
  // (0.061 + 0.1) kg * 9.81 = 1.58 N.
  EXPECT_EQ(Envelope(report, "load_after").verdict(), proto::PASS)
      << Envelope(report, "load_after").worst_value();
}

}  // namespace
}  // namespace hilrig::host
