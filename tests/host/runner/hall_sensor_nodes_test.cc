#include "host/runner/hall_sensor_nodes.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "host/sensors/earth_field.h"
#include "host/sensors/tactile/dipole_film_field.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "host/sensors/tactile/sensor_layout.h"
#include "rig/emulated_bus.h"
#include "rig/tactile_protocol.h"

namespace hilrig::host {
namespace {

constexpr std::int64_t kMs = 1'000'000;

HallSensorConfig ReferenceOnly(double rate_hz) {
  HallSensorConfig config;
  config.node_rate_hz = rate_hz;
  config.reference.node_id = tactile_bus::kReferenceNodeId;
  config.reference.film_present = false;
  return config;
}

std::vector<rig::TactileSample> Samples(const std::vector<rig::TimedCanFrame>& frames) {
  std::vector<rig::TactileSample> samples;
  for (const rig::TimedCanFrame& timed : frames) {
    if (auto sample = rig::DecodeTactileSample(timed.frame)) samples.push_back(sample.value());
  }
  return samples;
}

int StatusFrames(const std::vector<rig::TimedCanFrame>& frames) {
  int count = 0;
  for (const rig::TimedCanFrame& timed : frames)
    count += rig::DecodeTactileStatus(timed.frame).ok();
  return count;
}

// Ticks every tick_ns from 0 until end_ns (exclusive), then reads everything the bus carried.
std::vector<rig::TimedCanFrame> RunNodes(
    const HallSensorConfig& config, std::int64_t tick_ns, std::int64_t end_ns,
    std::shared_ptr<const FilmFieldModel> film = nullptr,
    const Eigen::Vector3d& pad_force_n = Eigen::Vector3d::Zero()) {
  rig::EmulatedBus bus;
  const EarthField earth;
  HallSensorNodes nodes(config, earth, 7, std::move(film), bus.Connect("nodes"));
  auto listener = bus.Connect("listener");
  std::array<Eigen::Vector3d, kTactileSensorCount> forces;
  forces.fill(pad_force_n);
  for (std::int64_t now_ns = 0; now_ns < end_ns; now_ns += tick_ns) {
    nodes.Tick(now_ns, Eigen::Quaterniond::Identity(), forces);
  }
  std::vector<rig::TimedCanFrame> frames;
  listener->Receive(end_ns + 10 * kMs, frames);
  return frames;
}

TEST(HallSensorNodesTest, FiftyHertzNodeSendsEverySlotOfASecondAtOneKilohertzTicks) {
  const std::vector<rig::TimedCanFrame> frames = RunNodes(ReferenceOnly(50), kMs, 1000 * kMs);

  const std::vector<rig::TactileSample> samples = Samples(frames);
  ASSERT_EQ(samples.size(), 50u);  // slots at 0, 20, ..., 980 ms
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(samples[i].node_id, tactile_bus::kReferenceNodeId);
    EXPECT_EQ(samples[i].sequence, i);
  }
  EXPECT_EQ(StatusFrames(frames), 1);  // at 0 s; the next is due at 1 s
}

TEST(HallSensorNodesTest, TicksThatDoNotDivideThePeriodMissNoSlot) {
  // 300 us ticks: the 20 ms slots fall between ticks and are taken at the next one.
  const std::vector<rig::TimedCanFrame> frames = RunNodes(ReferenceOnly(50), 300'000, 1000 * kMs);

  const std::vector<rig::TactileSample> samples = Samples(frames);
  ASSERT_EQ(samples.size(), 50u);
  EXPECT_EQ(samples.back().sequence, 49);
}

TEST(HallSensorNodesTest, TactileNodeReadsWhatTheSensorModelGivesForOnePeriodSteps) {
  HallSensorConfig config = ReferenceOnly(50);
  config.tactile_enabled = true;
  config.film_cross_talk = false;  // the one-off model call below knows nothing of the others
  for (std::size_t i = 0; i < config.tactile.size(); ++i) {
    config.tactile[i].node_id = static_cast<std::uint8_t>(i + 1);
  }
  auto film = std::make_shared<const DipoleFilmField>(DipoleFilmField::FromFilm(FilmGeometry{}));
  const Eigen::Vector3d force_n(0.05, -0.02, 0.3);

  const std::vector<rig::TactileSample> samples =
      Samples(RunNodes(config, kMs, 100 * kMs, film, force_n));

  // Node 1 alone, through the one-off model call with the 20 ms period spelled out.
  TactileSensorState state = InitialTactileSensorState(config.tactile[0], 7);
  std::vector<std::array<std::uint16_t, 3>> expected;
  for (int k = 0; k < 5; ++k) {
    expected.push_back(SampleTactileSensor(config.tactile[0], state, *film, force_n,
                                           Eigen::Quaterniond::Identity(),
                                           EarthField{}.field_world_t, 25.0, 0.02)
                           .code);
  }
  std::vector<std::array<std::uint16_t, 3>> node1;
  for (const rig::TactileSample& sample : samples) {
    if (sample.node_id == 1) node1.push_back(sample.code);
  }
  EXPECT_EQ(node1, expected);
}

// The reference node's z reading (tesla) in each of its samples.
std::vector<double> ReferenceZ(const std::vector<rig::TimedCanFrame>& frames,
                               const HallSensorConfig& config) {
  std::vector<double> z;
  for (const rig::TactileSample& sample : Samples(frames)) {
    if (sample.node_id != tactile_bus::kReferenceNodeId) continue;
    z.push_back(
        dut_fw::CodesToTesla<double>(config.reference.chip.setting, sample.code).field_t.z());
  }
  return z;
}

// With the reference 20 mm above an open frame, it reads Earth's field plus the six films' 30 uT
// (film_cross_talk.h); the same node without the cross-talk reads Earth's alone. Same seed, so the
// chip noise is the same draw and the difference is the films'.
TEST(HallSensorNodesTest, AReferenceNearTheRingReadsTheFilmsField) {
  HallSensorConfig config = ReferenceOnly(50);
  config.tactile_enabled = true;
  config.tactile = DefaultTactileLayout();
  config.reference.position_body_m = {0, 0, 0.020};
  config.film_cross_talk = true;
  auto film = std::make_shared<const DipoleFilmField>(DipoleFilmField::FromFilm(FilmGeometry{}));
  const std::vector<double> with = ReferenceZ(RunNodes(config, kMs, 100 * kMs, film), config);
  config.film_cross_talk = false;
  const std::vector<double> without = ReferenceZ(RunNodes(config, kMs, 100 * kMs, film), config);

  FilmCrossTalk expected(MakeCrossTalkFarField(), config.tactile, config.reference);
  std::array<Eigen::Vector3d, kTactileSensorCount> chips;
  for (int i = 0; i < kTactileSensorCount; ++i) chips[i] = config.tactile[i].position_body_m;
  std::array<FilmPose, kTactileSensorCount> rest;
  rest.fill(FilmPose{});
  expected.Update(chips, rest);
  ASSERT_GT(std::abs(expected.AtReferenceSensor().z()), 10e-6);
  ASSERT_EQ(with.size(), 5u);
  ASSERT_EQ(without.size(), 5u);
  for (std::size_t k = 0; k < with.size(); ++k) {
    // Within a quantization step (0.242 uT per LSB on z).
    EXPECT_NEAR(with[k] - without[k], expected.AtReferenceSensor().z(), 0.25e-6) << "sample " << k;
  }
}

// The nodes reuse one frame for sending: each must still be the classic frame of its own bytes,
// nothing of the one before past its length, status frames and samples alike.
TEST(HallSensorNodesTest, EveryFrameSentIsTheClassicFrameOfItsOwnPayload) {
  const std::vector<rig::TimedCanFrame> frames = RunNodes(ReferenceOnly(50), kMs, 1'100 * kMs);
  ASSERT_GT(StatusFrames(frames), 0);
  ASSERT_GT(Samples(frames).size(), 50u);
  for (const rig::TimedCanFrame& timed : frames) {
    const rig::CanFrame& frame = timed.frame;
    EXPECT_EQ(frame, rig::CanFrame::Classic(frame.id, frame.payload()));
    for (std::size_t i = frame.length; i < frame.data.size(); ++i) ASSERT_EQ(frame.data[i], 0);
  }
}

}  // namespace
}  // namespace hilrig::host
