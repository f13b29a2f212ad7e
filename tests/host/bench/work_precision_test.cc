#include "host/bench/work_precision.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "host/scenario/scenario_loader.h"
#include "rig/clock.h"

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;

CapturedTrace Trace(const std::vector<double>& time_s, const std::vector<double>& force_n,
                    const std::vector<double>& load_n, const std::vector<Eigen::Vector3d>& pos_m) {
  CapturedTrace trace;
  trace.time_s = time_s;
  trace.grasp_force_n = force_n;
  trace.load_n = load_n;
  trace.position_m = pos_m;
  return trace;
}

const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

TEST(CompareTracesTest, RmsAndMaxOfTheSampleDifferences) {
  const CapturedTrace reference =
      Trace({0.01, 0.02, 0.03, 0.04}, {1, 1, 1, 1}, {2, 2, 2, 2}, {kZero, kZero, kZero, kZero});
  const CapturedTrace run = Trace({0.01, 0.02, 0.03, 0.04}, {1, 2, 1, 3}, {2, 2, 1.5, 2},
                                  {kZero, Eigen::Vector3d(3, 4, 0), kZero, kZero});

  const ErrorMetrics errors = CompareTraces(run, reference);

  EXPECT_EQ(errors.samples_compared, 4u);
  EXPECT_TRUE(errors.complete());
  EXPECT_DOUBLE_EQ(errors.grasp_force_rms_n, std::sqrt((1.0 + 4.0) / 4));
  EXPECT_DOUBLE_EQ(errors.grasp_force_max_n, 2.0);
  EXPECT_DOUBLE_EQ(errors.load_rms_n, std::sqrt(0.25 / 4));
  EXPECT_DOUBLE_EQ(errors.load_max_n, 0.5);
  EXPECT_DOUBLE_EQ(errors.position_rms_m, std::sqrt(25.0 / 4));
  EXPECT_DOUBLE_EQ(errors.position_max_m, 5.0);
}

TEST(CompareTracesTest, ARunThatEndedEarlyCountsTheMissingSamples) {
  const CapturedTrace reference =
      Trace({0.01, 0.02, 0.03}, {1, 1, 1}, {0, 0, 0}, {kZero, kZero, kZero});
  const CapturedTrace run = Trace({0.01}, {1.5}, {0}, {kZero});

  const ErrorMetrics errors = CompareTraces(run, reference);

  EXPECT_EQ(errors.samples_compared, 1u);
  EXPECT_EQ(errors.samples_missing, 2u);
  EXPECT_FALSE(errors.complete());
  EXPECT_DOUBLE_EQ(errors.grasp_force_max_n, 0.5);
}

TEST(CompareTracesTest, NonFiniteSamplesAreMissingNotNaN) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const CapturedTrace reference = Trace({0.01, 0.02}, {1, 1}, {0, 0}, {kZero, kZero});
  const CapturedTrace run = Trace({0.01, 0.02}, {nan, 1.25}, {0, 0}, {kZero, kZero});

  const ErrorMetrics errors = CompareTraces(run, reference);

  EXPECT_EQ(errors.samples_missing, 1u);
  EXPECT_DOUBLE_EQ(errors.grasp_force_rms_n, 0.25);
}

TEST(CompareTracesTest, EmptyTracesGiveZeroNotNaN) {
  const ErrorMetrics errors = CompareTraces({}, {});

  EXPECT_EQ(errors.samples_compared, 0u);
  EXPECT_FALSE(errors.complete());
  EXPECT_EQ(errors.position_rms_m, 0.0);
}

TEST(CapturedTraceTest, KeepsTheSamplesColumnsExactly) {
  TraceSample sample;
  sample.time_s = 0.01;
  sample.position_m = Eigen::Vector3d(1.0 / 3, -0.1, 0.5);
  sample.grasp_force_n = 0.6000000000000001;
  sample.load_n = 2.37;
  CapturedTrace trace;

  trace.Add(sample);

  ASSERT_EQ(trace.size(), 1u);
  EXPECT_EQ(trace.time_s[0], 0.01);
  EXPECT_EQ(trace.position_m[0], Eigen::Vector3d(1.0 / 3, -0.1, 0.5));
  EXPECT_EQ(trace.grasp_force_n[0], 0.6000000000000001);
  EXPECT_EQ(trace.load_n[0], 2.37);
}

RunResult Result(RunKind kind, double wall_s_per_sim_s, double force_error_n) {
  RunResult run;
  run.run.kind = kind;
  run.wall_s_per_sim_s = wall_s_per_sim_s;
  run.errors.samples_compared = 10;
  run.errors.grasp_force_rms_n = force_error_n;
  return run;
}

TEST(ParetoFrontTest, KeepsOnlyNonDominatedRunsSortedByTimeWithoutTheReference) {
  const std::vector<RunResult> runs = {
      Result(RunKind::kReference, 10, 0), Result(RunKind::kIntegrator, 4, 1),
      Result(RunKind::kIntegrator, 1, 5), Result(RunKind::kField, 3, 4),
      Result(RunKind::kDefault, 2, 3)};

  EXPECT_THAT(ParetoFront(runs, ErrorMetric::kGraspForce), ElementsAre(2, 4, 1));
}

TEST(ParetoFrontTest, IncompleteRunsAreNotOnTheFront) {
  std::vector<RunResult> runs = {Result(RunKind::kIntegrator, 1, 0.1),
                                 Result(RunKind::kIntegrator, 2, 0.2)};
  runs[0].errors.samples_missing = 3;  // it stopped early: cheap because it did not finish

  EXPECT_THAT(ParetoFront(runs, ErrorMetric::kGraspForce), ElementsAre(1));
}

TEST(PlanSweepTest, FullSweepIsIntegratorsTimesStepsThenFieldsThenTheDefault) {
  FidelityChoice scene;
  scene.field_fidelity = "opmap:32";

  const std::vector<PlannedRun> runs = PlanSweep(scene, /*quick=*/false);

  ASSERT_EQ(runs.size(), 4u * 4u + 7u + 1u);
  EXPECT_EQ(runs[15].fidelity.integrator, proto::INTEGRATOR_DORMAND_PRINCE);
  EXPECT_EQ(runs[15].fidelity.plant_substeps, 8);
  EXPECT_EQ(runs[15].fidelity.integrator_tolerance, 1e-6);
  EXPECT_EQ(runs[15].fidelity.field_fidelity, "opmap:32");
  EXPECT_EQ(runs[16].kind, RunKind::kField);
  EXPECT_EQ(runs[16].fidelity.integrator, proto::INTEGRATOR_RK4);
  EXPECT_EQ(runs[16].fidelity.plant_substeps, 1);
  EXPECT_EQ(runs.back().kind, RunKind::kDefault);
  EXPECT_EQ(runs.back().fidelity.field_fidelity, "opmap:32");
}

TEST(PlanSweepTest, QuickSweepIsTwoIntegratorsTwoStepsTwoFields) {
  EXPECT_EQ(PlanSweep(FidelityChoice{}, /*quick=*/true).size(), 2u * 2u + 2u + 1u);
}

TEST(FidelityTest, WithFidelitySetsEveryChoiceInTheSpec) {
  proto::Scenario spec;
  const FidelityChoice reference = ReferenceFidelity(/*quick=*/false);

  const proto::Scenario changed = WithFidelity(spec, reference);

  EXPECT_EQ(changed.models().integrator(), proto::INTEGRATOR_DORMAND_PRINCE);
  EXPECT_EQ(changed.models().integrator_tolerance(), 1e-10);
  EXPECT_EQ(changed.simulation().plant_substeps(), 8u);
  EXPECT_EQ(changed.models().tactile().field_fidelity(), "tiles:64");
}

TEST(FidelityTest, SceneFidelityFillsTheResolverDefaults) {
  const FidelityChoice scene = SceneFidelity(proto::Scenario());

  EXPECT_EQ(scene.integrator, proto::INTEGRATOR_RK4);
  EXPECT_EQ(scene.plant_substeps, 1);
  EXPECT_EQ(scene.field_fidelity, "tiles:32");
  EXPECT_FALSE(scene.integrator_tolerance.has_value());
}

TEST(FidelityTest, TruncatedToDropsTimelineEntriesAfterTheEnd) {
  auto spec = LoadScenario(std::string(HILRIG_SOURCE_DIR) + "/scenarios/balloon_grasp.textproto");
  ASSERT_TRUE(spec.ok());

  const proto::Scenario cut = TruncatedTo(spec.value(), 8);

  EXPECT_EQ(cut.simulation().duration_s(), 8);
  ASSERT_EQ(cut.timeline_size(), 2);  // the grasp at 1.5 s and the setpoint at 7 s
  EXPECT_EQ(cut.timeline(1).at_s(), 7);
}

class CompareWithReferenceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto loaded = LoadScenario(std::string(HILRIG_SOURCE_DIR) + "/scenarios/hover.textproto");
    ASSERT_TRUE(loaded.ok());
    spec_ = TruncatedTo(loaded.value(), 2);
    spec_.mutable_models()->set_noise(proto::NOISE_OFF);
  }

  ScenarioConfig Resolved(const FidelityChoice& fidelity) {
    ScenarioConfig config = ResolveScenario(WithFidelity(spec_, fidelity), std::nullopt);
    EXPECT_TRUE(LoadTactileCalibration(config).ok());
    return config;
  }

  proto::Scenario spec_;
  rig::SimClock wall_clock_;  // timing is not what these tests check
};

TEST_F(CompareWithReferenceTest, TheReferenceAgainstItselfHasNoError) {
  const FidelityChoice reference = {proto::INTEGRATOR_RK4, std::nullopt, 2, "tiles:32"};
  const ScenarioConfig chosen = Resolved(reference);

  auto compared = CompareWithReference(chosen, spec_, "", reference, {&wall_clock_});

  ASSERT_TRUE(compared.ok()) << compared.error().message;
  EXPECT_EQ(compared.value().errors.samples_compared, 200u);  // 2 s at the 100 Hz trace rate
  EXPECT_EQ(compared.value().errors.position_max_m, 0.0);
}

TEST_F(CompareWithReferenceTest, ACoarserIntegratorHasASmallNonZeroPositionError) {
  const FidelityChoice reference = {proto::INTEGRATOR_RK4, std::nullopt, 4, "tiles:32"};
  const ScenarioConfig chosen =
      Resolved({proto::INTEGRATOR_SEMI_IMPLICIT_EULER, std::nullopt, 1, "tiles:32"});

  auto compared = CompareWithReference(chosen, spec_, "", reference, {&wall_clock_});

  ASSERT_TRUE(compared.ok()) << compared.error().message;
  EXPECT_TRUE(compared.value().errors.complete());
  // First-order steps of 1 ms against a closed loop that holds the vehicle within centimetres:
  // a difference above rounding, well below the loop's own 5 cm envelope.
  EXPECT_GT(compared.value().errors.position_max_m, 1e-12);
  EXPECT_LT(compared.value().errors.position_max_m, 1e-3);
}

TEST_F(CompareWithReferenceTest, AnUnknownReferenceFieldIsAnError) {
  spec_.mutable_models()->mutable_tactile()->set_enabled(true);
  const ScenarioConfig chosen = Resolved({proto::INTEGRATOR_RK4, std::nullopt, 1, "map:16"});

  auto compared = CompareWithReference(
      chosen, spec_, "", {proto::INTEGRATOR_RK4, std::nullopt, 1, "tiles:banana"}, {&wall_clock_});

  ASSERT_FALSE(compared.ok());
  EXPECT_THAT(compared.error().message, ::testing::HasSubstr("field_fidelity"));
}

TEST(AddReferenceMetricsTest, AddsTheFourMetrics) {
  ReferenceComparison comparison;
  comparison.errors.grasp_force_rms_n = 0.01;
  comparison.errors.load_rms_n = 0.02;
  comparison.errors.position_rms_m = 0.003;
  comparison.reference.set_wall_s(4.5);
  proto::Report report;

  AddReferenceMetrics(comparison, report);

  ASSERT_EQ(report.metrics_size(), 4);
  EXPECT_EQ(report.metrics(0).name(), "reference_error_grasp_force_rms_n");
  EXPECT_EQ(report.metrics(0).value(), 0.01);
  EXPECT_EQ(report.metrics(3).name(), "reference_wall_s");
  EXPECT_EQ(report.metrics(3).value(), 4.5);
}

}  // namespace
}  // namespace hilrig::host
