// The device seam: devices are ticked exactly at the events they declare, in the order they were
// added, never in between, and their metrics reach the run report.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "host/dut/in_process_dut.h"
#include "host/runner/device_emulator.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_loader.h"
#include "rig/emulated_bus.h"

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;

constexpr std::int64_t kMs = 1'000'000;

// Ticks every `period_ns` from `first_ns`, and writes down when (and in which order, in `order`).
class PeriodicDevice final : public DeviceEmulator {
 public:
  PeriodicDevice(std::string name, std::int64_t first_ns, std::int64_t period_ns,
                 std::vector<std::string>* order = nullptr)
      : name_(std::move(name)), next_ns_(first_ns), period_ns_(period_ns), order_(order) {}

  std::int64_t Initialize(const PlantView&, DutPort&) override { return next_ns_; }
  std::int64_t Tick(std::int64_t now_ns, const PlantView&, DutPort&) override {
    ticks_ns.push_back(now_ns);
    if (order_ != nullptr) order_->push_back(name_);
    next_ns_ += period_ns_;
    return next_ns_;
  }
  std::vector<rig::Metric> metrics() const override {
    return {{name_ + "_ticks", static_cast<double>(ticks_ns.size())}};
  }

  std::vector<std::int64_t> ticks_ns;

 private:
  std::string name_;
  std::int64_t next_ns_;
  std::int64_t period_ns_;
  std::vector<std::string>* order_;
};

ScenarioConfig ShortHover(double duration_s) {
  const auto spec = ParseScenario(R"(name: "air"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: )" + std::to_string(duration_s) +
                                      " }\n",
                                  "test.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), 1);
}

double Metric(const proto::Report& report, const std::string& name) {
  for (const auto& metric : report.metrics()) {
    if (metric.name() == name) return metric.value();
  }
  ADD_FAILURE() << "no metric " << name;
  return -1;
}

TEST(DeviceScheduleTest, ADeviceIsTickedExactlyAtItsEventsAndItsMetricsReachTheReport) {
  const ScenarioConfig config = ShortHover(0.02);
  ASSERT_EQ(config.physics_step_ns, 1 * kMs);
  PeriodicDevice device("fake", 0, 3 * kMs);
  const rig::SimClock wall_clock;
  RunControl control;
  control.wall_clock = &wall_clock;
  control.added_devices = {&device};
  const proto::Report report = RunScenario(config, {}, control);
  ASSERT_EQ(report.stop_reason(), "completed");
  EXPECT_THAT(device.ticks_ns,
              ElementsAre(0, 3 * kMs, 6 * kMs, 9 * kMs, 12 * kMs, 15 * kMs, 18 * kMs));
  EXPECT_EQ(Metric(report, "fake_ticks"), 7);
}

// An event between physics ticks is run at the first tick at or after it; the schedule keeps its
// own grid (the device's), so it does not drift with the tick.
TEST(DeviceScheduleTest, AnEventBetweenTicksRunsAtTheNextTick) {
  const ScenarioConfig config = ShortHover(0.01);
  PeriodicDevice device("offgrid", kMs / 2, 5 * kMs / 2);  // 0.5, 3, 5.5, 8 ms
  const rig::SimClock wall_clock;
  RunControl control;
  control.wall_clock = &wall_clock;
  control.added_devices = {&device};
  (void)RunScenario(config, {}, control);
  EXPECT_THAT(device.ticks_ns, ElementsAre(1 * kMs, 3 * kMs, 6 * kMs, 8 * kMs));
}

TEST(DeviceScheduleTest, DevicesTickInTheOrderTheyWereAddedAndOnlyWhenDue) {
  const ScenarioConfig config = ShortHover(1);
  std::vector<std::string> order;
  PeriodicDevice every_2ms("a", 0, 2 * kMs, &order);
  PeriodicDevice every_3ms("b", 0, 3 * kMs, &order);
  DeviceSchedule schedule;
  schedule.Add(every_2ms);
  schedule.Add(every_3ms);
  rig::EmulatedBus bus;
  InProcessDut dut(FirmwareFor(config), bus.Connect("dut"), 1e-3);
  const QuadrotorState vehicle;
  const std::array<Eigen::Vector3d, kGripperPadCount> pads = {};
  const PlantView plant{vehicle, pads};
  schedule.Initialize(plant, dut);
  for (std::int64_t now_ns = 0; now_ns <= 6 * kMs; now_ns += kMs) schedule.Tick(now_ns, plant, dut);
  EXPECT_THAT(order, ElementsAre("a", "b", "a", "b", "a", "a", "b"));
  ASSERT_EQ(every_2ms.metrics().size(), 1u);
  EXPECT_EQ(every_2ms.metrics()[0].name, "a_ticks");
  EXPECT_EQ(every_2ms.metrics()[0].value, 4);
  EXPECT_EQ(every_2ms.metrics()[0].unit, rig::Unit::kCount);
}

}  // namespace
}  // namespace hilrig::host
