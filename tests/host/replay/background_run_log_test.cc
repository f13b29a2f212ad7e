// The run's log on its own thread: whatever the loop logs comes out in the MCAP file in the order
// it was logged, across many batches, once Close has drained the queue.
#include "host/replay/background_run_log.h"

#include <gtest/gtest.h>

#include <sstream>

#include "host/mcap/mcap_reader.h"
#include "host/replay/recorded_traffic.h"

namespace hilrig::host {
namespace {

TEST(BackgroundRunLogTest, EverythingLoggedComesOutInOrderAfterClose) {
  std::ostringstream out;
  auto writer = RunLogWriter::Open(out, {});
  ASSERT_TRUE(writer.ok());
  proto::RunRecording recording;
  recording.mutable_spec()->set_name("queued");
  auto traffic = DutTrafficLog::Open(*writer.value(), recording);
  ASSERT_TRUE(traffic.ok());
  BackgroundRunLog log(std::move(writer).value(), std::move(traffic).value());
  constexpr int kTicks = 20000;  // many batches, more than the ring holds
  for (int tick = 0; tick < kTicks; ++tick) {
    const std::int64_t now_ns = tick * 1'000'000LL;
    ImuMessage imu;
    imu.stamp = {static_cast<std::uint64_t>(tick), now_ns};
    imu.gyro_rad_s.x() = tick;
    log.Sent(imu);
    log.Asked(tick, now_ns, std::nullopt);
    ActuatorMessage command;
    command.rotor_thrust_n[0] = tick;
    log.Answered(tick, now_ns, command, std::nullopt);
    if (tick % 10 == 0) {
      TraceSample sample;
      sample.time_s = tick * 1e-3;
      log.Add(sample);
    }
  }
  ASSERT_TRUE(log.Close().ok());
  ASSERT_TRUE(log.Close().ok());  // a second call does nothing

  const mcap::McapReadResult read = mcap::ReadMcap(out.str());
  ASSERT_TRUE(read.ok()) << read.error->detail;
  auto recorded = RecordedTraffic::Of(read.contents);
  ASSERT_TRUE(recorded.ok()) << recorded.error().message;
  EXPECT_EQ(recorded.value().recording().spec().name(), "queued");
  int next = 0, imu = 0, samples = 0;
  for (const mcap::McapMessage& message : read.contents.messages) {
    auto event = recorded.value().Decode(message);
    ASSERT_TRUE(event.ok());
    if (!event.value()) {
      samples += read.contents.channels.at(message.channel_id).topic == "/plant/vehicle";
      continue;
    }
    // Per tick: the IMU sample, the step, the command, in that order.
    const int tick = next / 3;
    if (const auto* input = std::get_if<DutInput>(&*event.value())) {
      ASSERT_EQ(next % 3, 0);
      EXPECT_EQ(std::get<ImuMessage>(*input).gyro_rad_s.x(), tick);
      ++imu;
    } else if (const auto* step = std::get_if<RecordedStep>(&*event.value())) {
      ASSERT_EQ(next % 3, 1);
      EXPECT_EQ(step->tick, static_cast<std::uint64_t>(tick));
    } else {
      ASSERT_EQ(next % 3, 2);
      EXPECT_EQ(std::get<RecordedCommand>(*event.value()).command.rotor_thrust_n[0], tick);
    }
    ++next;
  }
  EXPECT_EQ(imu, kTicks);
  EXPECT_EQ(next, 3 * kTicks);
  EXPECT_EQ(samples, kTicks / 10);
}

}  // namespace
}  // namespace hilrig::host
