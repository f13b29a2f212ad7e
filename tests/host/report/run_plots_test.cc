// The plots next to report.json: which files a run gets, that each shows the envelopes that watch
// its signals and the timeline's events, that a true force stays visible under its estimate, and
// that the top view draws the path.
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
    sample.position_m = Eigen::Vector3d(0.002 * i, -0.001 * i, 1.0 + 0.001 * i);
    sample.reference_m = Eigen::Vector3d(0, 0, 1.0);
    sample.grasp_force_n = 0.006 * i;
    sample.grasp_force_estimate_n = 0.006 * i;  // agrees exactly: both must still show
    for (std::size_t pad = 0; pad < kTracePadCount; ++pad) {
      sample.pad_force_n[pad] = 0.001 * i * static_cast<double>(pad + 1);
      sample.pad_force_estimate_n[pad] = sample.pad_force_n[pad] + 0.01;
    }
    trace.Add(sample);
  }
  return trace;
}

RunPlotScene GraspScene() {
  RunPlotScene scene;
  EnvelopeSpec pad = Envelope("pad_two", proto::PAD_FORCE_N, 0.5);
  pad.pad = 2;
  EnvelopeSpec ground = Envelope("clear_of_ground", proto::ALTITUDE_M, 0);
  ground.upper.reset();
  ground.lower = 0.05;
  scene.envelopes = {Envelope("grasp_force", proto::GRASP_FORCE_N, 0.65),
                     Envelope("altitude", proto::ALTITUDE_ERROR_M, 0.05), pad, ground};
  scene.grasp = true;
  scene.pads = true;
  scene.events = {{0.2, "grasp 0.6 N"}, {0.7, "stand removed"}, {5.0, "after the end"}};
  return scene;
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

TEST_F(RunPlotsTest, GraspSceneGetsEveryPlotEachWithItsEnvelopes) {
  const auto written = WriteRunPlots(ShortTrace(), GraspScene(), dir_.string());
  ASSERT_TRUE(written.ok()) << written.error().message;
  EXPECT_EQ(written.value(),
            (std::vector<std::string>{"force.svg", "pads.svg", "load.svg", "position.svg",
                                      "trajectory.svg", "top_view.svg"}));
  const std::string force = ReadFile(dir_ / "force.svg");
  EXPECT_NE(force.find("envelope grasp_force"), std::string::npos);
  EXPECT_EQ(force.find("envelope altitude"), std::string::npos);
  const std::string position = ReadFile(dir_ / "position.svg");
  EXPECT_NE(position.find("envelope altitude"), std::string::npos);
  EXPECT_EQ(position.find("envelope grasp_force"), std::string::npos);
  EXPECT_NE(ReadFile(dir_ / "pads.svg").find("envelope pad_two (pad 2)"), std::string::npos);
  // clear_of_ground watches the altitude: drawn on z.
  const std::string trajectory = ReadFile(dir_ / "trajectory.svg");
  EXPECT_NE(trajectory.find("envelope clear_of_ground"), std::string::npos);
  EXPECT_EQ(position.find("clear_of_ground"), std::string::npos);
}

TEST_F(RunPlotsTest, TimelineEventsAreMarkedOnThePlotsAgainstTime) {
  ASSERT_TRUE(WriteRunPlots(ShortTrace(), GraspScene(), dir_.string()).ok());
  for (const char* file : {"force.svg", "pads.svg", "load.svg", "position.svg", "trajectory.svg"}) {
    const std::string svg = ReadFile(dir_ / file);
    EXPECT_NE(svg.find("class=\"markers\""), std::string::npos) << file;
    EXPECT_NE(svg.find(">grasp 0.6 N<"), std::string::npos) << file;
    EXPECT_NE(svg.find(">stand removed<"), std::string::npos) << file;
    EXPECT_EQ(svg.find("after the end"), std::string::npos) << file;  // beyond the time axis
  }
  EXPECT_EQ(ReadFile(dir_ / "top_view.svg").find("class=\"markers\""), std::string::npos);
}

TEST_F(RunPlotsTest, TheTrueForceIsDrawnWideAndLightUnderItsEstimate) {
  ASSERT_TRUE(WriteRunPlots(ShortTrace(), GraspScene(), dir_.string()).ok());
  const std::string force = ReadFile(dir_ / "force.svg");
  const std::size_t true_line = force.find("stroke-width=\"4.5\" stroke-opacity=\"0.35\"");
  const std::size_t estimate_line = force.find("stroke-width=\"1.3\"");
  ASSERT_NE(true_line, std::string::npos);
  ASSERT_NE(estimate_line, std::string::npos);
  EXPECT_LT(true_line, estimate_line);  // later in the document is on top
}

std::size_t Count(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) {
    ++count;
  }
  return count;
}

TEST_F(RunPlotsTest, EachPadHasItsOwnPanelWithItsOwnEnvelopes) {
  ASSERT_TRUE(WriteRunPlots(ShortTrace(), GraspScene(), dir_.string()).ok());
  const std::string pads = ReadFile(dir_ / "pads.svg");
  for (std::size_t pad = 0; pad < kTracePadCount; ++pad) {
    EXPECT_NE(pads.find(">Pad " + std::to_string(pad) + " (node " + std::to_string(pad + 1) + ")<"),
              std::string::npos);
  }
  EXPECT_EQ(Count(pads, ">true (plant)<"), kTracePadCount);
  EXPECT_EQ(Count(pads, ">decoded by the DUT<"), kTracePadCount);
  EXPECT_EQ(Count(pads, "stroke-width=\"4.5\" stroke-opacity=\"0.35\""), 2 * kTracePadCount);
  // pad_two watches pad 2 only: its band and legend entry are in that panel alone.
  EXPECT_EQ(Count(pads, "envelope pad_two (pad 2)"), 1u);
  // Each panel clips to its own area.
  EXPECT_EQ(Count(pads, "<clipPath id="), kTracePadCount);
  EXPECT_NE(pads.find("id=\"plot-area-5\""), std::string::npos);
}

TEST_F(RunPlotsTest, TheTrajectoryHasXYAndZEachAgainstItsReference) {
  ASSERT_TRUE(WriteRunPlots(ShortTrace(), GraspScene(), dir_.string()).ok());
  const std::string trajectory = ReadFile(dir_ / "trajectory.svg");
  for (const char* label : {">x (m)<", ">y (m)<", ">z (m)<"}) {
    EXPECT_NE(trajectory.find(label), std::string::npos) << label;
  }
  EXPECT_EQ(Count(trajectory, ">reference<"), 3u);
  EXPECT_EQ(Count(trajectory, "envelope clear_of_ground"), 1u);  // on z only
}

TEST_F(RunPlotsTest, TheTopViewPutsXAlongAndYUp) {
  ASSERT_TRUE(WriteRunPlots(ShortTrace(), GraspScene(), dir_.string()).ok());
  const std::string top = ReadFile(dir_ / "top_view.svg");
  EXPECT_NE(top.find(">x (m)<"), std::string::npos);
  EXPECT_NE(top.find(">y (m)<"), std::string::npos);
  EXPECT_NE(top.find(">vehicle<"), std::string::npos);
  EXPECT_NE(top.find(">reference<"), std::string::npos);
  EXPECT_NE(top.find("<circle"), std::string::npos);  // the start
}

TEST_F(RunPlotsTest, SceneWithoutAnObjectOrPadsGetsThePositionPlotsOnly) {
  const auto written = WriteRunPlots(ShortTrace(), {}, dir_.string());
  ASSERT_TRUE(written.ok());
  EXPECT_EQ(written.value(),
            (std::vector<std::string>{"position.svg", "trajectory.svg", "top_view.svg"}));
  EXPECT_FALSE(fs::exists(dir_ / "force.svg"));
  EXPECT_FALSE(fs::exists(dir_ / "pads.svg"));
}

TEST_F(RunPlotsTest, UnwritableFolderIsAnError) {
  const auto written = WriteRunPlots(ShortTrace(), {}, (dir_ / "missing" / "x").string());
  EXPECT_FALSE(written.ok());
}

}  // namespace
}  // namespace hilrig::host
