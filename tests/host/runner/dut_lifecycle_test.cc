// The runner's side of the DUT lifecycle: Start before anything else, no message nor step for a
// DUT that did not start, and Stop once at the end of every run; the navigation sensors only for
// a DUT that takes them.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "host/runner/runner.h"
#include "host/scenario/scenario_loader.h"

namespace hilrig::host {
namespace {

// What the runner did to a DUT, in order ("start", "send", "step", "stop").
struct DutCalls {
  std::vector<std::string> calls;
  std::map<std::string, int> sent;  // by stream
  int accel_clipped = 0;            // IMU messages flagged
  int Count(const std::string& call) const {
    return static_cast<int>(std::count(calls.begin(), calls.end(), call));
  }
};

class RecordingDut final : public DutPort {
 public:
  RecordingDut(DutCalls& log, std::string start_error, bool navigation = false)
      : log_(log), start_error_(std::move(start_error)), navigation_(navigation) {}

  rig::Result<void> Start() override {
    log_.calls.push_back("start");
    if (!start_error_.empty()) return rig::MakeError(start_error_);
    return {};
  }
  void Stop() override { log_.calls.push_back("stop"); }
  void Send(const DutInput& input) override {
    log_.calls.push_back("send");
    ++log_.sent[DutInputStream(input.index())];
    if (const auto* imu = std::get_if<ImuMessage>(&input)) log_.accel_clipped += imu->accel_clipped;
  }
  bool TakesNavigationSensors() const override { return navigation_; }
  rig::Result<ActuatorMessage> Step(std::uint64_t, std::int64_t) override {
    log_.calls.push_back("step");
    return ActuatorMessage();
  }
  DutCounters counters() const override { return {}; }
  std::string description() const override { return "recording"; }

 private:
  DutCalls& log_;
  std::string start_error_;
  bool navigation_;
};

ScenarioConfig ShortHover() {
  const auto spec = ParseScenario(R"(name: "air"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: 0.01 }
)",
                                  "test.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), 1);
}

proto::Report RunWith(const ScenarioConfig& config, DutFactory factory) {
  const rig::SimClock wall_clock;
  RunControl control;
  control.wall_clock = &wall_clock;
  control.dut_factory = std::move(factory);
  return RunScenario(config, {}, control);
}

DutFactory Recording(DutCalls& log, const std::string& start_error, bool navigation = false) {
  return [&log, start_error, navigation](const ScenarioConfig&, std::unique_ptr<rig::CanBus>,
                                         double) -> rig::Result<std::unique_ptr<DutPort>> {
    return std::unique_ptr<DutPort>(std::make_unique<RecordingDut>(log, start_error, navigation));
  };
}

std::string ModelFidelity(const proto::Report& report, const std::string& name) {
  for (const proto::ModelInfo& model : report.models()) {
    if (model.name() == name) return model.fidelity();
  }
  ADD_FAILURE() << "no model " << name;
  return "";
}

TEST(DutLifecycleTest, ADutThatFailsToStartIsNeverSentNorSteppedAndIsStoppedOnce) {
  DutCalls log;
  const proto::Report report = RunWith(ShortHover(), Recording(log, "bench supply is off"));
  EXPECT_EQ(report.stop_reason(), "dut failed to start: bench supply is off");
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(report.ticks(), 0u);
  EXPECT_EQ(log.calls, (std::vector<std::string>{"start", "stop"}));
}

TEST(DutLifecycleTest, AStartedDutIsStartedFirstAndStoppedOnceAfterItsLastStep) {
  DutCalls log;
  const ScenarioConfig config = ShortHover();
  const proto::Report report = RunWith(config, Recording(log, ""));
  EXPECT_EQ(report.stop_reason(), "completed");
  ASSERT_GE(log.calls.size(), 3u);
  EXPECT_EQ(log.calls.front(), "start");
  EXPECT_EQ(log.calls.back(), "stop");
  EXPECT_EQ(log.Count("start"), 1);
  EXPECT_EQ(log.Count("stop"), 1);
  EXPECT_EQ(log.Count("step"), static_cast<int>(report.ticks() / config.control_every_ticks));
}

TEST(DutLifecycleTest, ARunnerDestroyedWithoutFinishStillStopsItsDut) {
  DutCalls log;
  const ScenarioConfig config = ShortHover();
  const rig::SimClock wall_clock;
  RunControl control;
  control.wall_clock = &wall_clock;
  control.dut_factory = Recording(log, "");
  {
    ScenarioRunner runner(config, {}, control);
    ASSERT_TRUE(runner.Tick());
  }
  EXPECT_EQ(log.Count("stop"), 1);
}

// A factory that cannot even build its DUT leaves no stand-in DUT behind: the report names none.
TEST(DutLifecycleTest, AFailedFactoryReportsNoDut) {
  const proto::Report report = RunWith(
      ShortHover(),
      [](const ScenarioConfig&, std::unique_ptr<rig::CanBus>,
         double) -> rig::Result<std::unique_ptr<DutPort>> { return rig::MakeError("no dut_emu"); });
  EXPECT_EQ(report.stop_reason(), "dut failed to start: no dut_emu");
  EXPECT_EQ(ModelFidelity(report, "dut"), "none (failed to start)");
}

double MetricOf(const proto::Report& report, const std::string& name) {
  for (const proto::Metric& metric : report.metrics()) {
    if (metric.name() == name) return metric.value();
  }
  ADD_FAILURE() << "no metric " << name;
  return -1;
}

// On the ground an accelerometer whose full scale is below gravity reads its range at every
// sample: the DUT is told on each, and the report counts them.
TEST(DutLifecycleTest, ClippedImuReadingsAreFlaggedToTheDutAndCounted) {
  ScenarioConfig config = ShortHover();
  config.duration_s = 0.1;
  config.initial_reference.position_m = Eigen::Vector3d::Zero();  // at rest on the ground
  config.imu.accel_range_m_s2 = 5.0;
  DutCalls log;
  const proto::Report report = RunWith(config, Recording(log, ""));
  EXPECT_EQ(log.sent["imu"], 100);
  EXPECT_EQ(log.accel_clipped, 100);
  EXPECT_EQ(MetricOf(report, "imu_accel_clipped_samples"), 100);
  EXPECT_EQ(MetricOf(report, "imu_gyro_clipped_samples"), 0);
}

// A flight stack that fuses a magnetometer, barometer and GNSS gets them on their own periods
// (100, 50 and 10 Hz, from time 0); the rig's own controller, which takes none, is sent none.
TEST(DutLifecycleTest, OnlyADutThatTakesThemIsSentTheNavigationSensors) {
  ScenarioConfig config = ShortHover();
  config.duration_s = 1.0;
  DutCalls flight_stack;
  RunWith(config, Recording(flight_stack, "", /*navigation=*/true));
  EXPECT_EQ(flight_stack.sent["mag"], 100);
  EXPECT_EQ(flight_stack.sent["baro"], 50);
  EXPECT_EQ(flight_stack.sent["gnss"], 10);
  EXPECT_EQ(flight_stack.sent["imu"], 1000);
  DutCalls own;
  RunWith(config, Recording(own, ""));
  EXPECT_EQ(own.sent["imu"], 1000);
  EXPECT_EQ(own.sent.count("mag") + own.sent.count("baro") + own.sent.count("gnss"), 0u);
}

// A DUT that does not count its front end's work (a board's firmware, a flight stack) gets no
// zeros in the report for it: those metrics are left out; the rig's own counts stay.
TEST(DutLifecycleTest, FrontEndCountsAreLeftOutForADutThatDoesNotCountThem) {
  DutCalls log;
  const proto::Report report = RunWith(ShortHover(), Recording(log, ""));
  std::vector<std::string> names;
  for (const proto::Metric& metric : report.metrics()) names.push_back(metric.name());
  for (const char* absent : {"dut_can_frames_rejected", "dut_sensor_samples",
                             "dut_sensor_samples_lost", "dut_tactile_samples_flagged"}) {
    EXPECT_EQ(std::count(names.begin(), names.end(), absent), 0) << absent;
  }
  EXPECT_EQ(std::count(names.begin(), names.end(), "dut_imu_messages"), 1);
}

}  // namespace
}  // namespace hilrig::host
