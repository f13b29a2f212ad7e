// A run's MCAP log read back with the rig's reader: the channels a scene gets, one message per
// channel per sample at its simulated time from the logs' epoch, each decoding to the sample's
// values, and the timeline's events interleaved where the trace passes them; the vehicle's pose on
// /tf and the reference path on /plant/reference_path in Foxglove's schemas; each envelope on
// /checks/<name> as its check reads each sample.
#include "host/report/run_log.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "host/mcap/mcap_reader.h"
#include "proto/foxglove/FrameTransform.pb.h"
#include "proto/foxglove/PosesInFrame.pb.h"
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
  ASSERT_EQ(ids.size(), 7u);
  for (const char* topic :
       {"/plant/vehicle", "/dut/estimates", "/plant/grasp", "/plant/pads", "/dut/pads", "/tf"}) {
    ASSERT_EQ(ids.count(topic), 1u) << topic;
    EXPECT_EQ(contents.statistics->channel_message_counts.at(ids.at(topic)), 5u) << topic;
    const mcap::McapSchema& schema =
        contents.schemas.at(contents.channels.at(ids.at(topic)).schema_id);
    EXPECT_EQ(schema.encoding, "protobuf");
  }
  EXPECT_EQ(contents.schemas.at(contents.channels.at(ids.at("/plant/vehicle")).schema_id).name,
            "hilrig.proto.VehicleTruth");
  EXPECT_EQ(contents.schemas.at(contents.channels.at(ids.at("/tf")).schema_id).name,
            "foxglove.FrameTransform");
  // The two pad channels share one schema.
  EXPECT_EQ(contents.schemas.size(), 6u);
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
  EXPECT_EQ(ids.size(),
            4u);  // no object, no pads, no reference path: vehicle, estimates, events, tf
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

TEST(RunLogTest, RollPitchYawTurnsYawThenPitchThenRoll) {
  const double quarter_turn_rad = std::numbers::pi / 2;
  // Rz(90 deg) * Rx(90 deg) = (cos 45 + k sin 45)(cos 45 + i sin 45) = (1 + i + j + k) / 2.
  const Eigen::Quaterniond q =
      QuaternionOfRollPitchYaw(Eigen::Vector3d(quarter_turn_rad, 0, quarter_turn_rad));
  EXPECT_NEAR(q.w(), 0.5, 1e-12);
  EXPECT_NEAR(q.x(), 0.5, 1e-12);
  EXPECT_NEAR(q.y(), 0.5, 1e-12);
  EXPECT_NEAR(q.z(), 0.5, 1e-12);
  // Pitch alone is a turn about y: half the angle in the quaternion.
  const Eigen::Quaterniond pitch = QuaternionOfRollPitchYaw(Eigen::Vector3d(0, 0.3, 0));
  EXPECT_NEAR(pitch.y(), std::sin(0.15), 1e-12);
  EXPECT_NEAR(pitch.w(), std::cos(0.15), 1e-12);
}

TEST(RunLogTest, TfCarriesTheBodyPoseInTheWorldAtTheSampleTime) {
  std::ostringstream out;
  auto log = RunLogWriter::Open(out, RunLogScene{});
  ASSERT_TRUE(log.ok()) << log.error().message;
  TraceSample sample = SampleAt(0);
  sample.time_s = 2.5;
  sample.position_m = Eigen::Vector3d(1, -2, 3);
  sample.roll_pitch_yaw_deg = Eigen::Vector3d(90, 0, 90);
  log.value()->Add(sample);
  ASSERT_TRUE(log.value()->Close().ok());
  const mcap::McapReadResult read = mcap::ReadMcap(out.str());
  ASSERT_TRUE(read.ok()) << read.error->detail;
  const auto ids = TopicIds(read.contents);
  int transforms = 0;
  for (const mcap::McapMessage& message : read.contents.messages) {
    if (message.channel_id != ids.at("/tf")) continue;
    ++transforms;
    EXPECT_EQ(static_cast<std::int64_t>(message.log_time_ns), kRunLogEpochNs + 2'500'000'000);
    foxglove::FrameTransform transform;
    ASSERT_TRUE(transform.ParseFromString(message.payload));
    EXPECT_EQ(transform.timestamp().seconds(), kRunLogEpochNs / 1'000'000'000 + 2);
    EXPECT_EQ(transform.timestamp().nanos(), 500'000'000);
    EXPECT_EQ(transform.parent_frame_id(), "world");
    EXPECT_EQ(transform.child_frame_id(), "body");
    EXPECT_EQ(transform.translation().x(), 1);
    EXPECT_EQ(transform.translation().y(), -2);
    EXPECT_EQ(transform.translation().z(), 3);
    EXPECT_NEAR(transform.rotation().w(), 0.5, 1e-12);
    EXPECT_NEAR(transform.rotation().x(), 0.5, 1e-12);
    EXPECT_NEAR(transform.rotation().y(), 0.5, 1e-12);
    EXPECT_NEAR(transform.rotation().z(), 0.5, 1e-12);
  }
  EXPECT_EQ(transforms, 1);
}

TEST(RunLogTest, TheReferencePathIsOneMessageAtTimeZero) {
  RunLogScene scene;
  scene.reference_path = {{Eigen::Vector3d(0, 0, 0), 0},
                          {Eigen::Vector3d(0, 0, 1), 0},
                          {Eigen::Vector3d(1, 0, 1), std::numbers::pi / 2}};
  const mcap::McapContents contents = WriteAndRead(scene, 3);
  const auto ids = TopicIds(contents);
  ASSERT_EQ(ids.count("/plant/reference_path"), 1u);
  EXPECT_EQ(
      contents.schemas.at(contents.channels.at(ids.at("/plant/reference_path")).schema_id).name,
      "foxglove.PosesInFrame");
  int paths = 0;
  for (const mcap::McapMessage& message : contents.messages) {
    if (message.channel_id != ids.at("/plant/reference_path")) continue;
    ++paths;
    EXPECT_EQ(static_cast<std::int64_t>(message.log_time_ns), kRunLogEpochNs);
    foxglove::PosesInFrame path;
    ASSERT_TRUE(path.ParseFromString(message.payload));
    EXPECT_EQ(path.frame_id(), "world");
    EXPECT_EQ(path.timestamp().seconds(), kRunLogEpochNs / 1'000'000'000);
    ASSERT_EQ(path.poses_size(), 3);
    EXPECT_EQ(path.poses(1).position().z(), 1);
    EXPECT_EQ(path.poses(0).orientation().w(), 1);
    EXPECT_NEAR(path.poses(2).orientation().z(), std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(path.poses(2).orientation().w(), std::sqrt(0.5), 1e-12);
  }
  EXPECT_EQ(paths, 1);
}

// Samples at 0, 0.01 and 0.02 s with a grasp force of 0.5, 0.5 and 0.7 N.
std::vector<proto::EnvelopeSample> EnvelopeSamples(const EnvelopeSpec& envelope) {
  RunLogScene scene;
  scene.envelopes = {envelope};
  std::ostringstream out;
  auto log = RunLogWriter::Open(out, scene);
  EXPECT_TRUE(log.ok()) << log.error().message;
  if (!log.ok()) return {};
  for (int i = 0; i < 3; ++i) {
    TraceSample sample = SampleAt(i);
    sample.grasp_force_n = i == 2 ? 0.7 : 0.5;
    log.value()->Add(sample);
  }
  EXPECT_TRUE(log.value()->Close().ok());
  const mcap::McapReadResult read = mcap::ReadMcap(out.str());
  EXPECT_TRUE(read.ok()) << read.error->detail;
  const auto ids = TopicIds(read.contents);
  const std::string topic = "/checks/" + envelope.name;
  EXPECT_EQ(ids.count(topic), 1u);
  if (ids.count(topic) == 0) return {};
  EXPECT_EQ(read.contents.schemas.at(read.contents.channels.at(ids.at(topic)).schema_id).name,
            "hilrig.proto.EnvelopeSample");
  std::vector<proto::EnvelopeSample> samples;
  for (const mcap::McapMessage& message : read.contents.messages) {
    if (message.channel_id != ids.at(topic)) continue;
    EXPECT_EQ(static_cast<std::int64_t>(message.log_time_ns),
              kRunLogEpochNs + static_cast<std::int64_t>(samples.size()) * 10'000'000);
    EXPECT_TRUE(samples.emplace_back().ParseFromString(message.payload));
  }
  return samples;
}

TEST(RunLogTest, AnEnvelopeGetsItsValueAndMarginWhileItChecks) {
  EnvelopeSpec envelope;
  envelope.name = "grasp_force";
  envelope.signal = proto::GRASP_FORCE_N;
  envelope.lower = 0.25;
  envelope.upper = 0.65;
  envelope.from_s = 0.005;
  const std::vector<proto::EnvelopeSample> samples = EnvelopeSamples(envelope);
  ASSERT_EQ(samples.size(), 3u);
  // Before its window: the bounds, nothing read.
  EXPECT_FALSE(samples[0].active());
  EXPECT_FALSE(samples[0].has_value());
  EXPECT_FALSE(samples[0].has_margin());
  EXPECT_FALSE(samples[0].violated());
  EXPECT_EQ(samples[0].lower(), 0.25);
  EXPECT_EQ(samples[0].upper(), 0.65);
  // 0.5 N: 0.15 N under the upper bound, nearer than the lower one.
  EXPECT_TRUE(samples[1].active());
  EXPECT_EQ(samples[1].value(), 0.5);
  EXPECT_NEAR(samples[1].margin(), 0.15, 1e-12);
  EXPECT_FALSE(samples[1].violated());
  // 0.7 N: 0.05 N over.
  EXPECT_TRUE(samples[2].active());
  EXPECT_EQ(samples[2].value(), 0.7);
  EXPECT_NEAR(samples[2].margin(), -0.05, 1e-12);
  EXPECT_TRUE(samples[2].violated());
}

TEST(RunLogTest, AMeanEnvelopeLogsTheMeanOnceItsWindowIsFull) {
  EnvelopeSpec envelope;
  envelope.name = "mean_force";
  envelope.signal = proto::GRASP_FORCE_N;
  envelope.upper = 0.65;
  envelope.mean_over_s = 0.02;
  const std::vector<proto::EnvelopeSample> samples = EnvelopeSamples(envelope);
  ASSERT_EQ(samples.size(), 3u);
  EXPECT_FALSE(samples[0].active());
  EXPECT_FALSE(samples[1].active());
  EXPECT_FALSE(samples[0].has_lower());
  // The window of 0.02 s at 0.02 s holds the samples at 0.01 and 0.02 s: (0.5 + 0.7) / 2.
  EXPECT_TRUE(samples[2].active());
  EXPECT_NEAR(samples[2].value(), 0.6, 1e-12);
  EXPECT_NEAR(samples[2].margin(), 0.05, 1e-12);
  EXPECT_FALSE(samples[2].violated());
}

}  // namespace
}  // namespace hilrig::host
