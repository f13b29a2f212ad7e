#include "host/pipeline/run_pipeline.h"

#include <gmock/gmock.h>
#include <google/protobuf/text_format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <variant>

#include "host/fidelity/fidelity_choice.h"
#include "host/report/run_plots.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "rig/clock.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// The shipped hover cut to two seconds: a whole scene that runs in a fraction of a second.
class RunPipelineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshTestDir("run_pipeline_");
    auto hover = LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto");
    ASSERT_TRUE(hover.ok()) << hover.error().message;
    spec_ = TruncatedTo(hover.value(), 2);
    // The shipped envelopes judge the settled hover, after 2 s; this one judges the take-off.
    spec_.clear_envelopes();
    proto::Envelope* near = spec_.add_envelopes();
    near->set_name("near_the_reference");
    near->set_signal(proto::POSITION_ERROR_M);
    near->set_upper(2);
    spec_path_ = (dir_ / "short_hover.textproto").string();
    std::string text;
    ASSERT_TRUE(google::protobuf::TextFormat::PrintToString(spec_, &text));
    std::ofstream(spec_path_) << text;
  }

  RunRequest Request() const {
    RunRequest request;
    request.spec_path = spec_path_;
    request.out_dir = (dir_ / "out").string();
    return request;
  }

  RunPipelineResult Run(const RunRequest& request) {
    return RunPipeline(request, {&wall_clock_, nullptr, nullptr, &notes_});
  }

  static std::size_t Lines(const std::string& text) {
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  }

  fs::path dir_;
  proto::Scenario spec_;
  std::string spec_path_;
  rig::SimClock wall_clock_;  // the wall time is not what these tests check
  std::ostringstream notes_;
};

TEST_F(RunPipelineTest, RunsASceneIntoItsFolderAndSaysWhatItWrote) {
  RunPipelineResult result = Run(Request());

  ASSERT_TRUE(std::holds_alternative<RunOutcome>(result)) << std::get<RunError>(result).message;
  const RunOutcome& outcome = std::get<RunOutcome>(result);
  EXPECT_EQ(outcome.verdict, RunVerdict::kPass);
  EXPECT_EQ(outcome.report.stop_reason(), "completed");
  EXPECT_EQ(outcome.report.spec_file(), spec_path_);
  EXPECT_FALSE(outcome.report.has_fidelity_error());  // none was asked for
  const fs::path out = dir_ / "out";
  for (const char* file :
       {"trace.csv", "can.log", "run.mcap", "junit.xml", "report.json", "index.html",
        kPositionPlotFile, kTrajectoryPlotFile, kTopViewPlotFile}) {
    EXPECT_THAT(outcome.files_written, ::testing::Contains((out / file).string()));
    EXPECT_GT(fs::file_size(out / file), 0u) << file;
  }
  // Hover has no object and no pads: no force, pad or load plot.
  EXPECT_EQ(outcome.files_written.size(), 9u);
  EXPECT_EQ(Lines(ReadFile(out / "trace.csv")), 1u + 200u);  // a header and 2 s at 100 Hz
  EXPECT_THAT(ReadFile(out / "report.json"), HasSubstr("\"completed\""));
  EXPECT_THAT(ReadFile(out / "index.html"), HasSubstr("id=\"plot0-plot-area\""));  // inlined
}

TEST_F(RunPipelineTest, WithoutTheLogTheFolderHasNoRunMcap) {
  RunRequest request = Request();
  request.run_log = false;
  RunPipelineResult result = Run(request);
  ASSERT_TRUE(std::holds_alternative<RunOutcome>(result)) << std::get<RunError>(result).message;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "run.mcap"));
  EXPECT_EQ(std::get<RunOutcome>(result).files_written.size(), 8u);
}

TEST_F(RunPipelineTest, ABadSpecIsATypedErrorAndWritesNoReport) {
  std::ofstream(spec_path_, std::ios::trunc) << "simulation { duration_s: -1 }\n";

  RunPipelineResult result = Run(Request());

  ASSERT_TRUE(std::holds_alternative<RunError>(result));
  const RunError& error = std::get<RunError>(result);
  EXPECT_EQ(error.failure, RunFailure::kBadSpec);
  EXPECT_THAT(error.message, HasSubstr(spec_path_));
  EXPECT_THAT(error.message, HasSubstr("duration_s"));
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(RunPipelineTest, AMissingSpecIsABadSpecNamingItsPath) {
  RunRequest request = Request();
  request.spec_path = (dir_ / "no_such.textproto").string();

  RunPipelineResult result = Run(request);

  ASSERT_TRUE(std::holds_alternative<RunError>(result));
  EXPECT_EQ(std::get<RunError>(result).failure, RunFailure::kBadSpec);
  EXPECT_THAT(std::get<RunError>(result).message, HasSubstr("no_such.textproto"));
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(RunPipelineTest, AnOutputFolderThatCannotBeMadeIsAnOutputError) {
  RunRequest request = Request();
  request.out_dir = UncreatableFolder("run_pipeline_blocked_").string();

  RunPipelineResult result = Run(request);

  ASSERT_TRUE(std::holds_alternative<RunError>(result));
  EXPECT_EQ(std::get<RunError>(result).failure, RunFailure::kOutput);
  EXPECT_THAT(std::get<RunError>(result).message, HasSubstr("blocker"));
}

TEST_F(RunPipelineTest, WithoutAnOutputFolderNothingIsWrittenAndTheReportIsReturned) {
  RunRequest request;
  request.spec = &spec_;  // already loaded, as the bench has it

  RunPipelineResult result = Run(request);

  ASSERT_TRUE(std::holds_alternative<RunOutcome>(result)) << std::get<RunError>(result).message;
  const RunOutcome& outcome = std::get<RunOutcome>(result);
  EXPECT_EQ(outcome.verdict, RunVerdict::kPass);
  EXPECT_EQ(outcome.report.stop_reason(), "completed");
  EXPECT_TRUE(outcome.files_written.empty());
  EXPECT_EQ(outcome.report.plots_size(), 0);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1)
      << "only the spec";
}

// The one capture of the run feeds both its plots and its comparison with the reference: a
// reference at the scene's own fidelity, with its seed, is the same run, so every one of the
// run's samples is compared and none differs.
TEST_F(RunPipelineTest, OneCaptureFeedsThePlotsAndTheComparison) {
  ReferenceSource reference;
  reference.fidelity = SceneFidelity(spec_);
  reference.notes = &notes_;
  RunRequest request = Request();
  request.reference = &reference;

  RunPipelineResult result = Run(request);

  ASSERT_TRUE(std::holds_alternative<RunOutcome>(result)) << std::get<RunError>(result).message;
  const RunOutcome& outcome = std::get<RunOutcome>(result);
  ASSERT_TRUE(outcome.report.has_fidelity_error()) << notes_.str();
  EXPECT_FALSE(outcome.no_fidelity_error.has_value());
  EXPECT_EQ(outcome.report.fidelity_error().samples_compared(), 200u);
  EXPECT_EQ(outcome.report.fidelity_error().position_max_m(), 0.0);
  // The plot drew the run's samples: it is not the plot of an empty capture with the same bands.
  const fs::path empty_dir = dir_ / "empty";
  fs::create_directories(empty_dir);
  RunPlotScene scene;
  scene.envelopes = ResolveScenario(spec_, std::nullopt).envelopes;
  ASSERT_TRUE(WriteRunPlots(PlottedTrace{}, scene, empty_dir.string()).ok());
  EXPECT_NE(ReadFile(dir_ / "out" / kPositionPlotFile), ReadFile(empty_dir / kPositionPlotFile));
  EXPECT_THAT(notes_.str(), HasSubstr("running the reference"));
}

TEST_F(RunPipelineTest, AReferenceThatCannotBeMadeLeavesTheVerdictAndSaysWhy) {
  ReferenceSource reference;
  reference.fidelity = SceneFidelity(spec_);
  reference.fidelity.integrator = proto::INTEGRATOR_DORMAND_PRINCE;
  reference.fidelity.integrator_tolerance = -1;
  RunRequest request = Request();
  request.reference = &reference;

  RunPipelineResult result = Run(request);

  ASSERT_TRUE(std::holds_alternative<RunOutcome>(result)) << std::get<RunError>(result).message;
  const RunOutcome& outcome = std::get<RunOutcome>(result);
  EXPECT_EQ(outcome.verdict, RunVerdict::kPass);
  EXPECT_FALSE(outcome.report.has_fidelity_error());
  ASSERT_TRUE(outcome.no_fidelity_error.has_value());
  EXPECT_THAT(*outcome.no_fidelity_error, HasSubstr("integrator_tolerance"));
  EXPECT_THAT(notes_.str(), HasSubstr(spec_path_ + ": no fidelity error: "));
}

TEST_F(RunPipelineTest, AStoppedRunIsNotComparedAndFails) {
  ReferenceSource reference;
  reference.fidelity = SceneFidelity(spec_);
  RunRequest request = Request();
  request.reference = &reference;
  const std::atomic<bool> stop{true};

  RunPipelineResult result = RunPipeline(request, {&wall_clock_, nullptr, &stop, &notes_});

  ASSERT_TRUE(std::holds_alternative<RunOutcome>(result)) << std::get<RunError>(result).message;
  const RunOutcome& outcome = std::get<RunOutcome>(result);
  EXPECT_EQ(outcome.verdict, RunVerdict::kCheckFailed);
  EXPECT_NE(outcome.report.stop_reason(), "completed");
  EXPECT_FALSE(outcome.report.has_fidelity_error());
  EXPECT_FALSE(outcome.no_fidelity_error.has_value());
  EXPECT_THAT(ReadFile(dir_ / "out" / "report.json"), HasSubstr(outcome.report.stop_reason()));
}

// A stop request during the DUT's calibration (tactile_hover without a calibration cache) ends the
// set-up as an interrupted run, not as a set-up that could not be made.
TEST_F(RunPipelineTest, AStopDuringTheCalibrationIsAnInterruptedRun) {
  RunRequest request;
  request.spec_path = ::hilrig::test_support::SourceDir() + "/scenarios/tactile_hover.textproto";
  const std::atomic<bool> stop{true};

  RunPipelineResult result = RunPipeline(request, {&wall_clock_, nullptr, &stop, &notes_});

  ASSERT_TRUE(std::holds_alternative<RunError>(result));
  const RunError& error = std::get<RunError>(result);
  EXPECT_EQ(error.failure, RunFailure::kInterrupted) << error.message;
  EXPECT_THAT(error.message, HasSubstr("tactile calibration: interrupted"));
}

}  // namespace
}  // namespace hilrig::host
