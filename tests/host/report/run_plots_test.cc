// The plots next to report.json: which files a run gets, and that each shows the envelopes that
// watch its signals.
#include "host/report/run_plots.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

EnvelopeSpec Envelope(const std::string& name, proto::Signal signal, double upper) {
  EnvelopeSpec envelope;
  envelope.name = name;
  envelope.signal = signal;
  envelope.upper = upper;
  return envelope;
}

PlottedTrace ShortTrace() {
  PlottedTrace trace;
  for (int i = 0; i < 100; ++i) {
    TraceSample sample;
    sample.time_s = i * 0.01;
    sample.position_m = Eigen::Vector3d(0, 0, 1.0 + 0.001 * i);
    sample.reference_m = Eigen::Vector3d(0, 0, 1.0);
    sample.grasp_force_n = 0.006 * i;
    trace.Add(sample);
  }
  return trace;
}

class RunPlotsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hilrig_run_plots_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(RunPlotsTest, GraspSceneGetsForceLoadAndPositionPlotsWithTheirEnvelopes) {
  const std::vector<EnvelopeSpec> envelopes = {Envelope("grasp_force", proto::GRASP_FORCE_N, 0.65),
                                               Envelope("altitude", proto::ALTITUDE_ERROR_M, 0.05)};
  const auto written = WriteRunPlots(ShortTrace(), envelopes, true, dir_.string());
  ASSERT_TRUE(written.ok()) << written.error().message;
  EXPECT_EQ(written.value(), (std::vector<std::string>{"force.svg", "load.svg", "position.svg"}));
  const std::string force = ReadFile(dir_ / "force.svg");
  EXPECT_NE(force.find("envelope grasp_force"), std::string::npos);
  EXPECT_EQ(force.find("envelope altitude"), std::string::npos);
  const std::string position = ReadFile(dir_ / "position.svg");
  EXPECT_NE(position.find("envelope altitude"), std::string::npos);
  EXPECT_EQ(position.find("envelope grasp_force"), std::string::npos);
}

TEST_F(RunPlotsTest, SceneWithoutAnObjectGetsThePositionPlotOnly) {
  const auto written = WriteRunPlots(ShortTrace(), {}, false, dir_.string());
  ASSERT_TRUE(written.ok());
  EXPECT_EQ(written.value(), std::vector<std::string>{"position.svg"});
  EXPECT_FALSE(fs::exists(dir_ / "force.svg"));
}

TEST_F(RunPlotsTest, UnwritableFolderIsAnError) {
  const auto written = WriteRunPlots(ShortTrace(), {}, false, (dir_ / "missing" / "x").string());
  EXPECT_FALSE(written.ok());
}

}  // namespace
}  // namespace hilrig::host
