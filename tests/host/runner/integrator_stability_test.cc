// Integrators and vehicle fidelity levels through the whole runner: an unstable step, or a spin
// the step cannot resolve, stops the run with "numerical instability" (and a complete report, no
// NaN in the trace), the reduced
// fidelity levels show in the trace what they promise and name themselves in the model list,
// and the hover scenario passes its envelopes with every integrator.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

struct RunOutput {
  proto::Report report;
  std::string trace;
};

RunOutput RunToEnd(const ScenarioConfig& config) {
  std::ostringstream trace, can_log;
  const rig::SimClock wall_clock;  // never moves: these tests ignore timing
  RunOutput output;
  RunControl control;
  control.wall_clock = &wall_clock;
  output.report = RunScenario(config, {.trace_csv = &trace, .can_log = &can_log}, control);
  output.trace = trace.str();
  return output;
}

ScenarioConfig ConfigFrom(const std::string& text) {
  const auto spec = ParseScenario(text, "test.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), 1);
}

// The trace as columns by header name.
class Trace {
 public:
  explicit Trace(const std::string& csv) {
    std::istringstream lines(csv);
    std::string line;
    std::getline(lines, line);
    header_ = Split(line);
    while (std::getline(lines, line)) rows_.push_back(Split(line));
  }
  std::vector<double> Column(const std::string& name) const {
    const auto at = std::find(header_.begin(), header_.end(), name);
    EXPECT_NE(at, header_.end()) << name;
    const auto index = static_cast<std::size_t>(at - header_.begin());
    std::vector<double> values;
    for (const auto& row : rows_) values.push_back(std::stod(row.at(index)));
    return values;
  }
  std::size_t rows() const { return rows_.size(); }

 private:
  static std::vector<std::string> Split(const std::string& line) {
    std::vector<std::string> cells;
    std::istringstream stream(line);
    std::string cell;
    while (std::getline(stream, cell, ',')) cells.push_back(cell);
    return cells;
  }
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

double Spread(const std::vector<double>& values) {
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return *hi - *lo;
}

std::string VehicleModel(const proto::Report& report) {
  for (const auto& model : report.models()) {
    if (model.name() == "vehicle") return model.fidelity();
  }
  return "";
}

double Metric(const proto::Report& report, const std::string& name) {
  for (const proto::Metric& metric : report.metrics()) {
    if (metric.name() == name) return metric.value();
  }
  ADD_FAILURE() << "no metric " << name;
  return -1;
}

// ---- Numerical instability --------------------------------------------------------------

// 10 Hz physics with the explicit midpoint rule, and a body whose roll inertia is 300x smaller
// than the others: the attitude loop at 10 Hz overshoots to rates where an explicit step of the
// gyroscopic terms (coefficient (Iy - Iz) / Ix = -200) diverges to infinity within a second.
constexpr const char* kUnstable = R"(name: "unstable"
vehicle { initial_position_m { z: 50 } inertia_kg_m2 { x: 1e-5 y: 3e-3 z: 5e-3 } }
models { integrator: INTEGRATOR_MIDPOINT }
simulation { duration_s: 30 physics_rate_hz: 10 trace_rate_hz: 10 }
timeline { at_s: 0 setpoint { position_m { z: 50 } } }
envelopes { name: "alt" signal: ALTITUDE_ERROR_M upper: 0.5 }
envelopes { name: "tilt" signal: TILT_DEG upper: 30 }
)";

TEST(IntegratorStabilityRunTest, UnstableStepStopsTheRunWithNumericalInstability) {
  const RunOutput output = RunToEnd(ConfigFrom(kUnstable));
  RecordProperty("stop_reason", output.report.stop_reason());
  EXPECT_THAT(output.report.stop_reason(), StartsWith("numerical instability"));
  EXPECT_EQ(output.report.stop_kind(), proto::STOP_NUMERICAL_INSTABILITY);
  EXPECT_LT(output.report.simulated_s(), 30.0) << output.report.stop_reason();
  EXPECT_FALSE(output.report.passed());
}

TEST(IntegratorStabilityRunTest, UnstableRunStillWritesACompleteReportWithoutNan) {
  const RunOutput output = RunToEnd(ConfigFrom(kUnstable));
  ASSERT_EQ(output.report.envelopes_size(), 2);
  for (const auto& envelope : output.report.envelopes()) {
    EXPECT_GT(envelope.samples_checked(), 0u) << envelope.name();
    EXPECT_TRUE(std::isfinite(envelope.worst_value())) << envelope.name();
  }
  EXPECT_FALSE(VehicleModel(output.report).empty());
  EXPECT_GT(Trace(output.trace).rows(), 0u);
  EXPECT_EQ(output.trace.find("nan"), std::string::npos);
  EXPECT_EQ(output.trace.find("inf"), std::string::npos);
}

TEST(IntegratorStabilityRunTest, SameSpecWithRk4AtOneKilohertzDoesNotBlowUp) {
  // The instability is the step, not the vehicle: at 1 kHz the same body stays finite.
  std::string spec = kUnstable;
  spec.replace(spec.find("physics_rate_hz: 10 "), 20, "physics_rate_hz: 1000 ");
  spec.replace(spec.find("INTEGRATOR_MIDPOINT"), 19, "INTEGRATOR_RK4");
  spec.replace(spec.find("duration_s: 30"), 14, "duration_s: 3");
  const RunOutput output = RunToEnd(ConfigFrom(spec));
  EXPECT_EQ(output.report.stop_reason(), "completed");
  // The largest rotation in one step, reported, stays far inside what RK4 resolves.
  EXPECT_LT(Metric(output.report, "plant_max_rotation_per_step_deg"), 1.0);
}

TEST(IntegratorStabilityRunTest, ASpinTheStepCannotResolveStopsTheRunThoughTheStateIsFinite) {
  // Semi-implicit Euler's implicit rate update cannot gain rotational energy from the gyroscopic
  // terms, so the state stays finite: but the overshooting attitude loop spins the vehicle to
  // thousands of rad/s, hundreds of radians per 100 ms step, which is no motion any more. The run
  // stops on it by name, as on a state that is not finite, and its trace holds no NaN.
  std::string spec = kUnstable;
  spec.replace(spec.find("INTEGRATOR_MIDPOINT"), 19, "INTEGRATOR_SEMI_IMPLICIT_EULER");
  const RunOutput output = RunToEnd(ConfigFrom(spec));
  EXPECT_EQ(output.report.stop_kind(), proto::STOP_NUMERICAL_INSTABILITY);
  EXPECT_THAT(output.report.stop_reason(), HasSubstr("rad per plant step at 0.2 s"));
  EXPECT_THAT(output.report.stop_reason(),
              HasSubstr("past the 1 rad a fixed-step integrator resolves"));
  EXPECT_LT(output.report.simulated_s(), 1.0);
  EXPECT_GT(Metric(output.report, "plant_max_rotation_per_step_deg"), 57.3);
  EXPECT_EQ(output.trace.find("nan"), std::string::npos);
}

// ---- Fidelity levels -------------------------------------------------------------------

// Climb to 1 m with a sideways setpoint and a sideways push the vehicle cannot follow.
constexpr const char* kClimbAndPush = R"(name: "levels"
vehicle { initial_position_m { x: 0.3 y: -0.2 z: 0 } initial_yaw_deg: 20 }
simulation { duration_s: 6 }
timeline { at_s: 0.5 setpoint { position_m { x: 1.3 y: -0.2 z: 1 } transition_s: 2 } }
timeline { at_s: 3 disturbance { force_world_n { x: 2 y: 1 } duration_s: 0.5 } }
envelopes { name: "alt" signal: ALTITUDE_ERROR_M upper: 0.05 from_s: 4 }
)";

ScenarioConfig WithFidelity(const char* level) {
  return ConfigFrom(std::string(kClimbAndPush) + "models { vehicle: " + level + " }\n");
}

TEST(VehicleFidelityRunTest, VerticalOneDofClimbsWithoutHorizontalMotionOrTilt) {
  // Straight up: a sideways setpoint would make the controller tilt for it and add collective
  // for the tilt, which the rail turns into climb (the level promises no attitude).
  const RunOutput output = RunToEnd(ConfigFrom(R"(name: "rail"
vehicle { initial_position_m { x: 0.3 y: -0.2 z: 0 } initial_yaw_deg: 20 }
models { vehicle: VEHICLE_VERTICAL_1DOF }
simulation { duration_s: 6 }
timeline { at_s: 0.5 setpoint { position_m { x: 0.3 y: -0.2 z: 1 } transition_s: 2 } }
timeline { at_s: 3 disturbance { force_world_n { x: 2 y: 1 } duration_s: 0.5 } }
envelopes { name: "alt" signal: ALTITUDE_ERROR_M upper: 0.05 from_s: 4 }
)"));
  const Trace trace(output.trace);
  EXPECT_EQ(output.report.stop_reason(), "completed");
  EXPECT_EQ(Spread(trace.Column("x_m")), 0.0);
  EXPECT_EQ(Spread(trace.Column("y_m")), 0.0);
  EXPECT_EQ(trace.Column("x_m").front(), 0.3);
  for (double tilt : trace.Column("tilt_deg")) EXPECT_LT(tilt, 1e-6);
  EXPECT_NEAR(trace.Column("yaw_deg").back(), 20.0, 1e-9);
  EXPECT_NEAR(trace.Column("z_m").back(), 1.0, 0.05);  // the altitude loop still works
}

TEST(VehicleFidelityRunTest, VerticalOneDofIsNamedInTheModelList) {
  const RunOutput output = RunToEnd(WithFidelity("VEHICLE_VERTICAL_1DOF"));
  EXPECT_THAT(VehicleModel(output.report), StartsWith("vertical 1-DoF"));
}

TEST(VehicleFidelityRunTest, FixedStandMovesNothingWhileTheRotorsRun) {
  const RunOutput output = RunToEnd(WithFidelity("VEHICLE_FIXED_STAND"));
  const Trace trace(output.trace);
  EXPECT_EQ(output.report.stop_reason(), "completed");
  for (const char* column : {"x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg"}) {
    EXPECT_EQ(Spread(trace.Column(column)), 0.0) << column;
  }
  EXPECT_EQ(trace.Column("z_m").front(), 0.0);
  // The controller asks for a climb it never gets: the rotors do spin up.
  const std::vector<double> thrust = trace.Column("thrust0_n");
  EXPECT_GT(*std::max_element(thrust.begin(), thrust.end()), 0.5);
}

TEST(VehicleFidelityRunTest, FixedStandIsNamedInTheModelList) {
  const RunOutput output = RunToEnd(WithFidelity("VEHICLE_FIXED_STAND"));
  EXPECT_THAT(VehicleModel(output.report), StartsWith("fixed stand"));
}

TEST(VehicleFidelityRunTest, ModelListNamesIntegratorAndDormandPrinceTolerance) {
  const RunOutput output = RunToEnd(
      ConfigFrom(std::string(kClimbAndPush) +
                 "models { integrator: INTEGRATOR_DORMAND_PRINCE integrator_tolerance: 1e-8 }\n"));
  EXPECT_THAT(VehicleModel(output.report), StartsWith("full 6-DoF rigid body"));
  EXPECT_THAT(VehicleModel(output.report), HasSubstr("Dormand-Prince RK5(4) (tolerance 1e-08)"));
}

// ---- The hover scenario with every integrator -----------------------------------------

class HoverWithIntegratorTest : public ::testing::TestWithParam<proto::Integrator> {};

TEST_P(HoverWithIntegratorTest, HoverScenarioPassesItsEnvelopes) {
  auto spec = LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto");
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  proto::Scenario scenario = std::move(spec).value();
  scenario.mutable_models()->set_integrator(GetParam());
  // Take-off, the 20 s hover window in part and the sideways step: 30 s instead of 40.
  scenario.mutable_simulation()->set_duration_s(30);
  const RunOutput output = RunToEnd(ResolveScenario(scenario, 1));
  EXPECT_EQ(output.report.stop_reason(), "completed");
  EXPECT_TRUE(output.report.passed());
  for (const auto& envelope : output.report.envelopes()) {
    EXPECT_EQ(envelope.verdict(), proto::PASS) << envelope.name();
  }
}

INSTANTIATE_TEST_SUITE_P(AllIntegrators, HoverWithIntegratorTest,
                         ::testing::Values(proto::INTEGRATOR_SEMI_IMPLICIT_EULER,
                                           proto::INTEGRATOR_MIDPOINT, proto::INTEGRATOR_RK4,
                                           proto::INTEGRATOR_DORMAND_PRINCE),
                         [](const auto& info) { return proto::Integrator_Name(info.param); });

}  // namespace
}  // namespace hilrig::host
