// The recording seam between the runner and a DUT: everything passes through unchanged, the sink
// hears each input, received frame, step and command, a step after the frames the DUT drained for
// it, and a real-time command is paired with the step it answers (skipped steps dropped).
#include "host/dut/dut_traffic.h"

#include <gtest/gtest.h>

#include <deque>
#include <string>
#include <vector>

#include "rig/emulated_bus.h"

namespace hilrig::host {
namespace {

// A sink that writes down what it hears, one line each.
struct ListeningSink final : DutTrafficSink {
  void Sent(const DutInput& input) override {
    heard.push_back(std::string("sent ") + DutInputStream(input.index()));
  }
  void Received(const rig::TimedCanFrame& frame) override {
    heard.push_back("frame " + std::to_string(frame.frame.id));
  }
  void Asked(std::uint64_t tick, std::int64_t now_ns, std::optional<std::int64_t> wall) override {
    heard.push_back("asked " + std::to_string(tick) + " at " + std::to_string(now_ns) +
                    (wall ? " wall " + std::to_string(*wall) : ""));
  }
  void Answered(std::uint64_t tick, std::int64_t now_ns, const ActuatorMessage& command,
                std::optional<std::int64_t> wall) override {
    heard.push_back("answered " + std::to_string(tick) + " at " + std::to_string(now_ns) +
                    " thrust " + std::to_string(command.rotor_thrust_n[0]) +
                    (wall ? " wall " + std::to_string(*wall) : ""));
  }
  std::vector<std::string> heard;
};

// A DUT that drains its bus at each step and answers with the tick as its thrust; in real time
// its answers wait in `ready` until polled.
class DrainingDut final : public DutPort {
 public:
  explicit DrainingDut(std::unique_ptr<rig::CanBus> bus) : bus_(std::move(bus)) {}
  void Send(const DutInput&) override {}
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override {
    std::vector<rig::TimedCanFrame> frames;
    bus_->Receive(now_ns, frames);
    ActuatorMessage command;
    command.answers_sequence = tick;
    command.rotor_thrust_n[0] = static_cast<double>(tick);
    return command;
  }
  void RequestStep(std::uint64_t tick, std::int64_t now_ns) override {
    ready.push_back(Step(tick, now_ns).value());
  }
  rig::Result<std::optional<ActuatorMessage>> PollCommand() override {
    if (ready.empty()) return std::optional<ActuatorMessage>();
    ActuatorMessage newest = ready.back();
    ready.clear();
    return std::optional<ActuatorMessage>(newest);
  }
  DutCounters counters() const override { return {}; }
  std::string description() const override { return "draining"; }
  std::deque<ActuatorMessage> ready;

 private:
  std::unique_ptr<rig::CanBus> bus_;
};

struct SteppingWallClock final : rig::Clock {
  std::int64_t NowNs() const override { return now_ns += 10; }
  mutable std::int64_t now_ns = 1000;
};

TEST(DutTrafficTest, AStepIsHeardAfterTheFramesTheDutDrainedForIt) {
  rig::EmulatedBus bus(rig::EmulatedBusConfig{});
  auto sensor = bus.Connect("sensor");
  ListeningSink sink;
  RecordingDutPort dut(
      std::make_unique<DrainingDut>(std::make_unique<RecordingCanBus>(bus.Connect("dut"), sink)),
      sink, nullptr);
  ASSERT_TRUE(sensor->Send(rig::CanFrame::Classic(0x123, std::vector<std::uint8_t>{1, 2}), 0).ok());
  dut.Send(DutInput(ImuMessage{}));
  const auto command = dut.Step(0, 1'000'000);
  ASSERT_TRUE(command.ok());
  EXPECT_EQ(command.value().rotor_thrust_n[0], 0.0);
  EXPECT_EQ(sink.heard, (std::vector<std::string>{"sent imu", "frame 291", "asked 0 at 1000000",
                                                  "answered 0 at 1000000 thrust 0.000000"}));
}

TEST(DutTrafficTest, ARealTimeCommandIsPairedWithItsStepAndCarriesWallTimes) {
  rig::EmulatedBus bus(rig::EmulatedBusConfig{});
  ListeningSink sink;
  SteppingWallClock wall;
  auto inner = std::make_unique<DrainingDut>(bus.Connect("dut"));
  RecordingDutPort dut(std::move(inner), sink, &wall);
  dut.RequestStep(0, 0);
  dut.RequestStep(1, 1000);  // the DUT answers only the newer one
  const auto polled = dut.PollCommand();
  ASSERT_TRUE(polled.ok() && polled.value().has_value());
  EXPECT_EQ(polled.value()->answers_sequence, 1u);
  ASSERT_EQ(sink.heard.size(), 3u);
  EXPECT_EQ(sink.heard[0], "asked 0 at 0 wall 10");
  EXPECT_EQ(sink.heard[1], "asked 1 at 1000 wall 20");
  EXPECT_EQ(sink.heard[2], "answered 1 at 1000 thrust 1.000000 wall 30");
  EXPECT_EQ(dut.description(), "draining");
}

}  // namespace
}  // namespace hilrig::host
