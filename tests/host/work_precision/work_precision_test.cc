#include "host/work_precision/work_precision.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>

#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"
#include "rig/clock.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;

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

TEST(ParetoFrontTest, TimesWithinTheMarginDoNotDominateEqualErrors) {
  // The same error, timed 10 % apart: timing noise, so both stay; 30 % apart: the slower goes.
  const std::vector<RunResult> close = {Result(RunKind::kIntegrator, 1.0, 2),
                                        Result(RunKind::kDefault, 1.1, 2)};
  const std::vector<RunResult> far = {Result(RunKind::kIntegrator, 1.0, 2),
                                      Result(RunKind::kDefault, 1.3, 2.01)};

  EXPECT_THAT(ParetoFront(close, ErrorMetric::kGraspForce), ElementsAre(0, 1));
  EXPECT_THAT(ParetoFront(far, ErrorMetric::kGraspForce), ElementsAre(0));
  EXPECT_THAT(ParetoFront(close, ErrorMetric::kGraspForce, {0.0, 0.0}), ElementsAre(0));
}

TEST(ParetoFrontTest, AClearlyMoreAccurateRunDominatesAtAboutTheSameTime) {
  const std::vector<RunResult> runs = {Result(RunKind::kIntegrator, 1.05, 1.0),
                                       Result(RunKind::kDefault, 1.0, 2.0)};

  EXPECT_THAT(ParetoFront(runs, ErrorMetric::kGraspForce), ElementsAre(0));
}

TEST(ParetoFrontTest, ErrorsBelowTheFloorAreTiesWhateverTheirRatio) {
  // 2e-33 against 1e-33 N is rounding; 2e-6 against 1e-6 N is a model error.
  const std::vector<RunResult> rounding = {Result(RunKind::kIntegrator, 1.0, 2e-33),
                                           Result(RunKind::kDefault, 1.1, 1e-33)};
  const std::vector<RunResult> model = {Result(RunKind::kIntegrator, 1.0, 2e-6),
                                        Result(RunKind::kDefault, 1.1, 1e-6)};
  const std::vector<RunResult> slower_rounding = {Result(RunKind::kIntegrator, 1.0, 2e-33),
                                                  Result(RunKind::kDefault, 1.5, 1e-33)};

  EXPECT_THAT(ParetoFront(rounding, ErrorMetric::kGraspForce), ElementsAre(0, 1));
  EXPECT_THAT(ParetoFront(model, ErrorMetric::kGraspForce), ElementsAre(1));
  EXPECT_THAT(ParetoFront(slower_rounding, ErrorMetric::kGraspForce), ElementsAre(0));
  EXPECT_THAT(ParetoFront(rounding, ErrorMetric::kGraspForce, {0.15, 0.02, 0.0}), ElementsAre(1));
}

RunResult WithLoadError(RunResult run, double load_error_n) {
  run.errors.load_rms_n = load_error_n;
  return run;
}

TEST(ParetoFrontTest, TheJointFrontKeepsARunThatIsBestInAnyOneError) {
  // 0: fastest, best force error, worst load error. 1: slower, best load error. 2: slower than 0
  // and worse than 0 in force and than 1 in load, but not worse than both in both: it stays.
  // 3: as slow as 1 and worse in both errors than 1: dominated.
  const std::vector<RunResult> runs = {WithLoadError(Result(RunKind::kIntegrator, 1.0, 1.0), 8.0),
                                       WithLoadError(Result(RunKind::kIntegrator, 2.0, 3.0), 1.0),
                                       WithLoadError(Result(RunKind::kDefault, 1.5, 2.0), 2.0),
                                       WithLoadError(Result(RunKind::kField, 2.0, 4.0), 1.5)};
  const ErrorMetric both[] = {ErrorMetric::kGraspForce, ErrorMetric::kLoad};

  EXPECT_THAT(ParetoFront(runs, both), ElementsAre(0, 2, 1));
  EXPECT_THAT(ParetoFront(runs, ErrorMetric::kGraspForce), ElementsAre(0));
  EXPECT_THAT(ParetoFront(runs, ErrorMetric::kLoad), ElementsAre(0, 2, 1));
}

TEST(ParetoFrontTest, MarkParetoFrontsFlagsTheJointFront) {
  SceneResult scene;
  scene.runs = {Result(RunKind::kReference, 10, 0),
                WithLoadError(Result(RunKind::kIntegrator, 1.0, 1.0), 1.0),
                WithLoadError(Result(RunKind::kDefault, 1.5, 2.0), 2.0)};

  MarkParetoFronts(scene);

  EXPECT_FALSE(scene.runs[0].on_joint_front);  // the reference is never on a front
  EXPECT_TRUE(scene.runs[1].on_joint_front);
  EXPECT_FALSE(scene.runs[2].on_joint_front);  // slower and worse in every error
}

TEST(ParetoFrontTest, TheRecommendedRunIsTheCheapestPassingOneOnTheJointFront) {
  // 1: fastest, on the front, fails its envelopes. 2: next fastest on the front, passes.
  // 3: slower and less accurate than 2, off the front. 4: slowest, most accurate, passes.
  SceneResult scene;
  scene.scene = "scene";
  scene.runs = {Result(RunKind::kReference, 10, 0), Result(RunKind::kIntegrator, 1.0, 3.0),
                Result(RunKind::kIntegrator, 2.0, 2.0), Result(RunKind::kDefault, 2.5, 2.5),
                Result(RunKind::kField, 4.0, 1.0)};
  scene.runs[2].passes_envelopes = scene.runs[3].passes_envelopes = true;
  scene.runs[4].passes_envelopes = true;
  MarkParetoFronts(scene);

  EXPECT_EQ(CheapestPassingFrontRun(scene), &scene.runs[2]);
  EXPECT_THAT(FormatParetoTables(scene),
              ::testing::HasSubstr("scene: the cheapest run on the joint front that passes is "));
  for (RunResult& run : scene.runs) run.passes_envelopes = false;
  EXPECT_EQ(CheapestPassingFrontRun(scene), nullptr);
  EXPECT_THAT(FormatParetoTables(scene), ::testing::HasSubstr("that passes is none\n"));
}

TEST(ParetoFrontTest, TheDefaultsVerdictSaysWhenTheSweepWasCutShort) {
  SceneResult scene;
  scene.scene = "scene";
  scene.runs = {Result(RunKind::kReference, 10, 0), Result(RunKind::kDefault, 1.0, 1.0)};
  MarkParetoFronts(scene);

  EXPECT_THAT(FormatParetoTables(scene), ::testing::HasSubstr("does NOT pass its envelopes\n"));
  scene.cut_to_s = 3.0;
  EXPECT_THAT(
      FormatParetoTables(scene),
      ::testing::HasSubstr("does NOT pass its envelopes over the sweep's first 3 s (a "
                           "check whose window starts later has nothing to judge there)\n"));
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

  const std::vector<PlannedRun> runs = PlanSweep(scene, /*has_film=*/true, /*quick=*/false);

  // RK4 x1 opmap:32 is both a sweep point and the scene's own choice: planned once, as default.
  ASSERT_EQ(runs.size(), 4u * 4u + 7u + 1u - 2u);
  EXPECT_EQ(runs[14].fidelity.integrator, proto::INTEGRATOR_DORMAND_PRINCE);
  EXPECT_EQ(runs[14].fidelity.plant_substeps, 8);
  EXPECT_EQ(runs[14].fidelity.integrator_tolerance, 1e-6);
  EXPECT_EQ(runs[14].fidelity.field_fidelity, "opmap:32");
  EXPECT_EQ(runs[15].kind, RunKind::kField);
  EXPECT_EQ(runs[15].fidelity.integrator, proto::INTEGRATOR_RK4);
  EXPECT_EQ(runs[15].fidelity.plant_substeps, 1);
  EXPECT_EQ(runs.back().kind, RunKind::kDefault);
  EXPECT_EQ(runs.back().fidelity, scene);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    for (std::size_t j = i + 1; j < runs.size(); ++j) {
      EXPECT_FALSE(runs[i].fidelity == runs[j].fidelity) << i << " and " << j;
    }
  }
}

TEST(PlanSweepTest, QuickSweepIsTwoIntegratorsTwoStepsTwoFields) {
  // The scene's RK4 x1 tiles:32 is the default; nothing else coincides with it.
  EXPECT_EQ(PlanSweep(SceneFidelity(proto::Scenario()), true, /*quick=*/true).size(),
            2u * 2u + 2u + 1u - 1u);
}

TEST(PlanSweepTest, ASceneWithoutAFilmSweepsNoFieldLevels) {
  const std::vector<PlannedRun> runs =
      PlanSweep(SceneFidelity(proto::Scenario()), /*has_film=*/false, /*quick=*/false);

  EXPECT_EQ(runs.size(), 4u * 4u);
  EXPECT_TRUE(std::none_of(runs.begin(), runs.end(),
                           [](const PlannedRun& run) { return run.kind == RunKind::kField; }));
}

TEST(PlanSweepTest, EachSweptEffectIsOneRunAtTheScenesOwnFidelityBeforeTheDefault) {
  FidelityChoice scene;
  scene.field_fidelity = "opmap:32";
  const std::vector<SensorEffect> effects = {SensorEffect::kEarthField,
                                             SensorEffect::kChipEncoding};

  const std::vector<PlannedRun> runs = PlanSweep(scene, /*has_film=*/true, /*quick=*/true, effects);

  ASSERT_EQ(runs.size(), 2u * 2u + 2u + 2u + 1u - 1u);
  for (std::size_t i = 0; i < effects.size(); ++i) {
    const PlannedRun& run = runs[runs.size() - 3 + i];
    EXPECT_EQ(run.kind, RunKind::kEffect);
    EXPECT_EQ(run.fidelity.effect_off, effects[i]);
    FidelityChoice without = run.fidelity;
    without.effect_off.reset();
    EXPECT_EQ(without, scene);
  }
  EXPECT_EQ(runs.back().kind, RunKind::kDefault);
  EXPECT_EQ(FidelityLabel(runs[runs.size() - 3].fidelity), "RK4 x1 opmap:32 without earth_field");
}

// Every effect names a switch of models.tactile: switching it off in a spec turns it off there and
// nothing else.
TEST(SweptEffectsTest, SwitchingAnEffectOffSetsItsOwnSceneSwitch) {
  proto::Scenario spec;
  spec.mutable_models()->mutable_tactile()->set_enabled(true);
  for (SensorEffect effect : kSensorEffects) {
    FidelityChoice fidelity = SceneFidelity(spec);
    fidelity.effect_off = effect;
    const proto::Scenario off = WithFidelity(spec, fidelity);
    for (SensorEffect other : kSensorEffects) {
      EXPECT_EQ(EffectOn(off.models().tactile(), other), other != effect && OnByDefault(other))
          << SensorEffectName(effect) << " off, " << SensorEffectName(other);
    }
  }
}

TEST(SweptEffectsTest, TheSweepTakesTheScenesOnEffectsButNotTheNoise) {
  proto::Scenario spec;
  proto::Tactile& tactile = *spec.mutable_models()->mutable_tactile();
  tactile.set_enabled(true);
  EXPECT_THAT(SweptEffects(spec),
              ElementsAre(SensorEffect::kEarthField, SensorEffect::kSiliconeDamping,
                          SensorEffect::kChipSaturation, SensorEffect::kChipEncoding));
  tactile.set_earth_field(false);
  tactile.set_silicone_stiffening(true);
  EXPECT_THAT(SweptEffects(spec),
              ElementsAre(SensorEffect::kSiliconeDamping, SensorEffect::kSiliconeStiffening,
                          SensorEffect::kChipSaturation, SensorEffect::kChipEncoding));
}

TEST(SweptEffectsTest, TheTightestForceEnvelopeIsTheNarrowestPassingOneInNewtons) {
  proto::Scenario spec;
  const auto add = [&spec](proto::Signal signal, std::optional<double> lower,
                           std::optional<double> upper, proto::Verdict expect) {
    proto::Envelope& envelope = *spec.add_envelopes();
    envelope.set_signal(signal);
    if (lower) envelope.set_lower(*lower);
    if (upper) envelope.set_upper(*upper);
    envelope.set_expect(expect);
  };
  EXPECT_TRUE(std::isnan(TightestForceEnvelopeN(spec)));
  add(proto::GRASP_FORCE_N, 0.25, 0.65, proto::PASS);
  EXPECT_DOUBLE_EQ(TightestForceEnvelopeN(spec), 0.4);
  add(proto::ALTITUDE_ERROR_M, std::nullopt, 0.01, proto::PASS);  // metres: not a force
  add(proto::GRASP_FORCE_N, std::nullopt, 0.001, proto::FAIL);    // an ablation's
  EXPECT_DOUBLE_EQ(TightestForceEnvelopeN(spec), 0.4);
  add(proto::GRASP_FORCE_ERROR_N, std::nullopt, 0.05, proto::PASS);
  EXPECT_DOUBLE_EQ(TightestForceEnvelopeN(spec), 0.05);
}

// An effect whose removal adds 1 mN to a 0.05 N envelope may go; one that adds 10 mN, or whose run
// fails, stays. Effect runs are no candidates for the fronts.
TEST(SweptEffectsTest, TheEffectTableSaysWhichEffectsTheSceneCouldDrop) {
  SceneResult scene;
  scene.scene = "grasp";
  scene.tightest_force_envelope_n = 0.05;
  scene.runs = {Result(RunKind::kReference, 10, 0), Result(RunKind::kDefault, 2, 0.003)};
  scene.runs[1].passes_envelopes = true;
  const auto effect_run = [&](SensorEffect effect, double error_n, bool passes) {
    RunResult run = Result(RunKind::kEffect, 1, error_n);
    run.run.fidelity.effect_off = effect;
    run.passes_envelopes = passes;
    scene.runs.push_back(run);
  };
  effect_run(SensorEffect::kChipEncoding, std::sqrt(0.003 * 0.003 + 0.001 * 0.001), true);
  effect_run(SensorEffect::kEarthField, std::sqrt(0.003 * 0.003 + 0.01 * 0.01), true);
  effect_run(SensorEffect::kSiliconeDamping, 0.003, false);
  // Without saturation the true forces are the default's, but a check on the DUT's estimate
  // moves by 4 mN: more than 5 % of 0.05 N.
  effect_run(SensorEffect::kChipSaturation, 0.003, true);
  scene.runs[1].force_check_worst_n = {{"estimate", 0.010}};
  scene.runs.back().force_check_worst_n = {{"estimate", 0.014}};

  const std::string table = EffectTable(scene);

  EXPECT_THAT(table, ::testing::ContainsRegex("chip_encoding +0.00316 .* 0.001 .* pass +yes"));
  EXPECT_THAT(table, ::testing::ContainsRegex("earth_field +0.0104 .* 0.01 .* pass +no"));
  EXPECT_THAT(table, ::testing::ContainsRegex("chip_saturation +0.003 .* 0 +0.004 .* pass +no"));
  EXPECT_THAT(table, ::testing::ContainsRegex("silicone_damping .* FAIL +no \\(fails\\)"));
  EXPECT_THAT(ParetoFront(scene.runs, ErrorMetric::kGraspForce), ElementsAre(1));
  // Where the default fails too (a sweep cut short), the failure is not the effect's.
  scene.runs[1].passes_envelopes = false;
  EXPECT_THAT(EffectTable(scene), ::testing::ContainsRegex("silicone_damping .* FAIL +yes"));
  scene.tightest_force_envelope_n = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(EffectTable(scene), ::testing::HasSubstr("no force envelope"));
}

class SweepTimingTest : public ::testing::Test {
 protected:
  SceneResult Sweep(int timing_repeats) {
    auto loaded = LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto");
    EXPECT_TRUE(loaded.ok());
    SweepOptions options;
    options.quick = true;
    options.duration_s = 0.5;
    options.timing_repeats = timing_repeats;
    options.cheap_run_wall_s = std::numeric_limits<double>::infinity();
    RunControl control;
    control.wall_clock = &wall_clock_;
    auto scene = SweepScene(loaded.value(), "", options, control);
    EXPECT_TRUE(scene.ok()) << scene.error().message;
    return scene.ok() ? scene.value() : SceneResult{};
  }

  rig::SimClock wall_clock_;  // every run takes no wall time: each is cheap to repeat
};

TEST_F(SweepTimingTest, CheapRunsAreTimedInRoundsAsOftenAsAsked) {
  const SceneResult scene = Sweep(3);

  ASSERT_GT(scene.runs.size(), 4u);
  for (const RunResult& run : scene.runs) {
    EXPECT_EQ(run.timing_runs, 3);
  }
}

TEST_F(SweepTimingTest, OneRepeatKeepsTheCapturedTiming) {
  const SceneResult scene = Sweep(1);

  ASSERT_GT(scene.runs.size(), 4u);
  for (const RunResult& run : scene.runs) {
    EXPECT_EQ(run.timing_runs, 1);
  }
  EXPECT_TRUE(scene.shipped.passed) << "hover as shipped, whole, meets its verdicts";
  EXPECT_EQ(scene.shipped.stop_reason, "completed");
}

// An envelope only a noise-free hover can meet: the default passes in the sweep's noise-free runs
// and misses it as shipped, which is what RunDefaultAsShipped is there to tell.
class ShippedVerdictTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto loaded = LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto");
    ASSERT_TRUE(loaded.ok());
    spec_ = loaded.value();
    proto::Envelope* still = spec_.add_envelopes();
    still->set_name("still_without_noise");
    still->set_signal(proto::POSITION_ERROR_M);
    still->set_upper(1e-6);  // without noise the settled hover is within 4e-9 m
    still->set_from_s(12);
    still->set_until_s(24);
    control_.wall_clock = &wall_clock_;
  }

  proto::Scenario spec_;
  rig::SimClock wall_clock_;
  RunControl control_;
};

TEST_F(ShippedVerdictTest, NoiseTheSweepLeavesOutCanMissAVerdict) {
  auto shipped = RunDefaultAsShipped(spec_, "", control_);
  ASSERT_TRUE(shipped.ok()) << shipped.error().message;
  EXPECT_FALSE(shipped.value().passed);
  EXPECT_EQ(shipped.value().missed, std::vector<std::string>{"still_without_noise"});
  EXPECT_EQ(shipped.value().stop_reason, "completed");

  spec_.mutable_models()->set_noise(proto::NOISE_OFF);
  auto noise_free = RunDefaultAsShipped(spec_, "", control_);
  ASSERT_TRUE(noise_free.ok()) << noise_free.error().message;
  EXPECT_TRUE(noise_free.value().passed) << "the same envelope without noise";
  EXPECT_TRUE(noise_free.value().missed.empty());
}

}  // namespace
}  // namespace hilrig::host
