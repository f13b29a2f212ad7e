// A run's MCAP log read back with the rig's reader: the channels a scene gets, one message per
// channel per sample at its simulated time from the logs' epoch, each decoding to the sample's
// values, and the timeline's events interleaved where the trace passes them.
#include "host/report/run_log.h"

#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "host/mcap/mcap_reader.h"
#include "proto/run_log.pb.h"

namespace hilrig::host {
namespace {

TraceSample SampleAt(int i) {
  TraceSample sample;
  sample.time_s = 0.01 * i;
  sample.position_m = Eigen::Vector3d(0.1 * i, -0.2, 1.0);
  sample.reference_m = Eigen::Vector3d(0, 0, 1.0);
  sample.rotor_thrust_n = {1, 2, 3, 4};
  sample.grasp_force_n = 0.5;
  sample.grasp_force_estimate_n = 0.51;
  sample.object_held = i >= 2;
  sample.pad_force_n = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  sample.pad_force_estimate_n = {1.1, 1.2, 1.3, 1.4, 1.5, 1.6};
  return sample;
}

mcap::McapContents WriteAndRead(const RunLogScene& scene, int samples) {
  std::ostringstream out;
  auto log = RunLogWriter::Open(out, scene);
  EXPECT_TRUE(log.ok()) << log.error().message;
  if (!log.ok()) return {};
  for (int i = 0; i < samples; ++i) log.value()->Add(SampleAt(i));
  EXPECT_TRUE(log.value()->Close().ok());
  const mcap::McapReadResult read = mcap::ReadMcap(out.str());
  EXPECT_TRUE(read.ok()) << read.error->detail;
  return read.contents;
}

std::map<std::string, std::uint16_t> TopicIds(const mcap::McapContents& contents) {
  std::map<std::string, std::uint16_t> ids;
  for (const auto& [id, channel] : contents.channels) ids[channel.topic] = id;
  return ids;
}

TEST(RunLogTest, AGraspSceneWithPadsGetsEveryChannelOnePerSample) {
  RunLogScene scene;
  scene.grasp = true;
  scene.pads = true;
  const mcap::McapContents contents = WriteAndRead(scene, 5);
  const auto ids = TopicIds(contents);
  ASSERT_EQ(ids.size(), 6u);
  for (const char* topic :
       {"/plant/vehicle", "/dut/estimates", "/plant/grasp", "/plant/pads", "/dut/pads"}) {
    ASSERT_EQ(ids.count(topic), 1u) << topic;
    EXPECT_EQ(contents.statistics->channel_message_counts.at(ids.at(topic)), 5u) << topic;
    const mcap::McapSchema& schema =
        contents.schemas.at(contents.channels.at(ids.at(topic)).schema_id);
    EXPECT_EQ(schema.encoding, "protobuf");
  }
  EXPECT_EQ(contents.schemas.at(contents.channels.at(ids.at("/plant/vehicle")).schema_id).name,
            "hilrig.proto.VehicleTruth");
  // The two pad channels share one schema.
  EXPECT_EQ(contents.schemas.size(), 5u);
  EXPECT_EQ(contents.channels.at(ids.at("/plant/pads")).schema_id,
            contents.channels.at(ids.at("/dut/pads")).schema_id);
}

TEST(RunLogTest, EachMessageDecodesToItsSampleAtItsTime) {
  RunLogScene scene;
  scene.grasp = true;
  scene.pads = true;
  const mcap::McapContents contents = WriteAndRead(scene, 4);
  const auto ids = TopicIds(contents);
  int vehicles = 0, pads = 0, grasps = 0;
  for (const mcap::McapMessage& message : contents.messages) {
    const int i = static_cast<int>(
        (static_cast<std::int64_t>(message.log_time_ns) - kRunLogEpochNs + 5'000'000) / 10'000'000);
    const TraceSample sample = SampleAt(i);
    EXPECT_EQ(static_cast<std::int64_t>(message.log_time_ns),
              kRunLogEpochNs + static_cast<std::int64_t>(i) * 10'000'000);
    if (message.channel_id == ids.at("/plant/vehicle")) {
      proto::VehicleTruth vehicle;
      ASSERT_TRUE(vehicle.ParseFromString(message.payload));
      EXPECT_EQ(vehicle.position_m().x(), sample.position_m.x());
      EXPECT_EQ(vehicle.position_error_m().y(), -0.2);
      ASSERT_EQ(vehicle.rotor_thrust_n_size(), 4);
      EXPECT_EQ(vehicle.rotor_thrust_n(3), 4);
      ++vehicles;
    } else if (message.channel_id == ids.at("/dut/pads")) {
      proto::PadForces decoded;
      ASSERT_TRUE(decoded.ParseFromString(message.payload));
      ASSERT_EQ(decoded.force_n_size(), 6);
      EXPECT_EQ(decoded.force_n(5), 1.6);
      ++pads;
    } else if (message.channel_id == ids.at("/plant/grasp")) {
      proto::GraspTruth grasp;
      ASSERT_TRUE(grasp.ParseFromString(message.payload));
      EXPECT_EQ(grasp.grasp_force_n(), 0.5);
      EXPECT_EQ(grasp.object_held(), i >= 2);
      ++grasps;
    }
  }
  EXPECT_EQ(vehicles, 4);
  EXPECT_EQ(pads, 4);
  EXPECT_EQ(grasps, 4);
}

TEST(RunLogTest, EventsComeWhereTheTracePassesThemAndNotAfterTheRun) {
  RunLogScene scene;
  scene.events = {{0.0, "grasp 0.6 N"}, {0.015, "stand removed"}, {9.0, "after the end"}};
  const mcap::McapContents contents = WriteAndRead(scene, 3);  // samples at 0, 0.01, 0.02 s
  const auto ids = TopicIds(contents);
  EXPECT_EQ(ids.size(), 3u);  // no object, no pads: vehicle, estimates, events
  std::vector<std::string> labels;
  std::vector<std::uint64_t> times;
  for (const mcap::McapMessage& message : contents.messages) {
    if (message.channel_id != ids.at("/run/events")) continue;
    proto::TimelineMark mark;
    ASSERT_TRUE(mark.ParseFromString(message.payload));
    labels.push_back(mark.label());
    times.push_back(message.log_time_ns);
  }
  EXPECT_EQ(labels, (std::vector<std::string>{"grasp 0.6 N", "stand removed"}));
  ASSERT_EQ(times.size(), 2u);
  EXPECT_EQ(static_cast<std::int64_t>(times[1]), kRunLogEpochNs + 15'000'000);
}

}  // namespace
}  // namespace hilrig::host
