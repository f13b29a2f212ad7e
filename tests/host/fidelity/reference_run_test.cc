#include "host/fidelity/reference_run.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <string>

#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"
#include "rig/clock.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

class FidelityErrorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto loaded = LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto");
    ASSERT_TRUE(loaded.ok());
    spec_ = TruncatedTo(loaded.value(), 2);
    spec_.mutable_models()->set_noise(proto::NOISE_OFF);
  }
  void TearDown() override { std::filesystem::remove_all(cache_dir_); }

  ScenarioConfig Resolved(const FidelityChoice& fidelity) {
    ScenarioConfig config = ResolveScenario(WithFidelity(spec_, fidelity), std::nullopt);
    EXPECT_TRUE(LoadTactileCalibration(config).ok());
    return config;
  }

  rig::Result<proto::FidelityError> ErrorOf(const FidelityChoice& chosen_fidelity,
                                            const ReferenceSource& source) {
    const ScenarioConfig chosen = Resolved(chosen_fidelity);
    RunControl control;
    control.wall_clock = &wall_clock_;
    const CapturedRun run = RunCaptured(chosen, control);
    return FidelityErrorOf(chosen, run.trace, spec_, "", source, control);
  }

  proto::Scenario spec_;
  static ReferenceSource Source(const FidelityChoice& fidelity,
                                const ReferenceCache* cache = nullptr, std::string code = "") {
    ReferenceSource source;
    source.fidelity = fidelity;
    source.cache = cache;
    source.code_identity = std::move(code);
    return source;
  }

  rig::SimClock wall_clock_;  // timing is not what these tests check
  const std::string cache_dir_ = ::testing::TempDir() + "/fidelity_error_cache";
};

TEST_F(FidelityErrorTest, TheReferenceAgainstItselfHasNoError) {
  const FidelityChoice reference = {proto::INTEGRATOR_RK4, std::nullopt, 2, "tiles:32",
                                    std::nullopt};

  auto error = ErrorOf(reference, Source(reference));

  ASSERT_TRUE(error.ok()) << error.error().message;
  EXPECT_EQ(error.value().samples_compared(), 200u);  // 2 s at the 100 Hz trace rate
  EXPECT_EQ(error.value().position_max_m(), 0.0);
  EXPECT_EQ(error.value().reference_fidelity(), "RK4 x2 tiles:32");
  EXPECT_FALSE(error.value().reference_cached());
}

TEST_F(FidelityErrorTest, ACoarserIntegratorHasASmallNonZeroPositionError) {
  const FidelityChoice reference = {proto::INTEGRATOR_RK4, std::nullopt, 4, "tiles:32",
                                    std::nullopt};

  auto error =
      ErrorOf({proto::INTEGRATOR_SEMI_IMPLICIT_EULER, std::nullopt, 1, "tiles:32", std::nullopt},
              Source(reference));

  ASSERT_TRUE(error.ok()) << error.error().message;
  // First-order steps of 1 ms against a closed loop that holds the vehicle within centimetres:
  // a difference above rounding, well below the loop's own 5 cm envelope.
  EXPECT_GT(error.value().position_max_m(), 1e-12);
  EXPECT_LT(error.value().position_max_m(), 1e-3);
  EXPECT_LE(error.value().position_rms_m(), error.value().position_max_m());
}

TEST_F(FidelityErrorTest, AnUnknownReferenceFieldIsAnError) {
  spec_.mutable_models()->mutable_tactile()->set_enabled(true);

  auto error =
      ErrorOf({proto::INTEGRATOR_RK4, std::nullopt, 1, "map:16", std::nullopt},
              Source({proto::INTEGRATOR_RK4, std::nullopt, 1, "tiles:banana", std::nullopt}));

  ASSERT_FALSE(error.ok());
  EXPECT_THAT(error.error().message, ::testing::HasSubstr("field_fidelity"));
}

// A stop request that cuts the reference run short is an interruption, not a failed reference.
TEST_F(FidelityErrorTest, AReferenceRunAStopRequestEndedIsInterrupted) {
  const FidelityChoice reference = {proto::INTEGRATOR_RK4, std::nullopt, 2, "tiles:32",
                                    std::nullopt};
  const ScenarioConfig chosen = Resolved(reference);
  RunControl control;
  control.wall_clock = &wall_clock_;
  const CapturedRun run = RunCaptured(chosen, control);
  const std::atomic<bool> stop_requested{true};
  control.stop_requested = &stop_requested;

  auto error = FidelityErrorOf(chosen, run.trace, spec_, "", Source(reference), control);

  ASSERT_FALSE(error.ok());
  EXPECT_EQ(error.error().code, rig::ErrorCode::kInterrupted);
  EXPECT_EQ(error.error().message, "the reference run stopped short: interrupted");
}

TEST_F(FidelityErrorTest, TheSecondRunTakesTheReferenceFromTheCacheWithTheSameErrors) {
  const ReferenceCache cache(cache_dir_);
  ReferenceSource source =
      Source({proto::INTEGRATOR_RK4, std::nullopt, 4, "tiles:32", std::nullopt}, &cache, "code-a");
  const FidelityChoice chosen = {proto::INTEGRATOR_SEMI_IMPLICIT_EULER, std::nullopt, 1, "tiles:32",
                                 std::nullopt};

  auto first = ErrorOf(chosen, source);
  auto second = ErrorOf(chosen, source);
  source.code_identity = "code-b";  // another build: its own reference
  auto rebuilt = ErrorOf(chosen, source);

  ASSERT_TRUE(first.ok() && second.ok() && rebuilt.ok());
  EXPECT_FALSE(first.value().reference_cached());
  EXPECT_TRUE(second.value().reference_cached());
  EXPECT_FALSE(rebuilt.value().reference_cached());
  EXPECT_GT(first.value().position_max_m(), 0.0);
  EXPECT_EQ(second.value().position_max_m(), first.value().position_max_m());
  EXPECT_EQ(second.value().position_rms_m(), first.value().position_rms_m());
}

// The run is compared with its reference as it goes, reading the cache entry a block at a time.
// An entry cut after it was checked (another process, a full disk) ends in an error naming it,
// never in the error of a shorter reference.
TEST_F(FidelityErrorTest, AReferenceEntryCutDuringTheRunIsAnErrorNotANumber) {
  auto loaded = LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto");
  ASSERT_TRUE(loaded.ok());
  spec_ = TruncatedTo(loaded.value(), 20);  // 2000 samples: more than one block of the entry
  spec_.mutable_models()->set_noise(proto::NOISE_OFF);
  const FidelityChoice fidelity = {proto::INTEGRATOR_RK4, std::nullopt, 2, "tiles:32",
                                   std::nullopt};
  const ReferenceCache cache(cache_dir_);
  const ReferenceSource source = Source(fidelity, &cache, "code-a");
  ASSERT_TRUE(ErrorOf(fidelity, source).ok());  // stores the entry
  const ScenarioConfig chosen = Resolved(fidelity);
  RunControl control;
  control.wall_clock = &wall_clock_;
  auto comparison = FidelityComparison::Start(chosen, spec_, "", source, control);
  ASSERT_TRUE(comparison.ok()) << comparison.error().message;

  for (const auto& entry : std::filesystem::directory_iterator(cache_dir_)) {
    if (entry.path().extension() == ".ref") {
      std::filesystem::resize_file(entry.path(), std::filesystem::file_size(entry.path()) / 2);
    }
  }
  const CapturedRun run = RunCaptured(chosen, control);
  for (std::size_t i = 0; i < run.trace.size(); ++i) comparison.value()->Add(run.trace.At(i));
  auto error = comparison.value()->Finish();

  ASSERT_FALSE(error.ok());
  EXPECT_THAT(error.error().message, ::testing::HasSubstr("shorter than its header says"));
}

}  // namespace
}  // namespace hilrig::host
