#include "host/runner/hall_sensor_nodes.h"

#include <cmath>

#include "host/sensors/tactile/memoized_film_field.h"
#include "rig/sensor_frame.h"

namespace hilrig::host {
namespace {

// The reference node carries no film; it is given one it never reads.
class NoFilm final : public FilmFieldModel {
 public:
  Eigen::Vector3d FieldAtChip(const FilmPose&) const override { return Eigen::Vector3d::Zero(); }
};

}  // namespace

HallSensorNodes::HallSensorNodes(const HallSensorConfig& config, const EarthField& earth_field,
                                 std::uint64_t seed, std::shared_ptr<const FilmFieldModel> film,
                                 std::unique_ptr<rig::CanBus> bus)
    : config_(config),
      earth_field_(earth_field),
      film_(film ? std::shared_ptr<const FilmFieldModel>(
                       std::make_shared<const MemoizedFilmField>(std::move(film)))
                 : std::make_shared<const NoFilm>()),
      bus_(std::move(bus)),
      reference_state_(InitialTactileSensorState(config.reference, seed)),
      period_ns_(std::llround(1e9 / config.node_rate_hz)) {
  for (int i = 0; i < kTactileSensorCount; ++i) {
    tactile_states_[i] = InitialTactileSensorState(config.tactile[i], seed);
  }
}

void HallSensorNodes::SampleNode(const TactileSensorParams& params, TactileSensorState& state,
                                 std::uint8_t& sequence, const Eigen::Vector3d& pad_force_n,
                                 const Eigen::Quaterniond& attitude_world_body,
                                 std::int64_t now_ns) {
  const TactileReading reading = SampleTactileSensor(
      params, state, *film_, pad_force_n, attitude_world_body, earth_field_.field_world_t,
      config_.temperature_c, static_cast<double>(period_ns_) / 1e9);
  rig::MagneticSample sample;
  sample.node_id = params.node_id;
  // The frame carries the chip's 16-bit result words as they are; the DUT decodes the RES format.
  sample.x_code = static_cast<std::int16_t>(reading.code[0]);
  sample.y_code = static_cast<std::int16_t>(reading.code[1]);
  sample.z_code = static_cast<std::int16_t>(reading.code[2]);
  sample.sequence = sequence++;
  sample.status = reading.saturated ? rig::kSensorStatusSaturated : 0;
  if (bus_->Send(rig::EncodeMagneticSample(sample), now_ns).ok()) {
    ++frames_sent_;
  } else {
    ++frames_dropped_;  // a full or bus-off bus loses the sample; the DUT sees the sequence gap
  }
}

void HallSensorNodes::Tick(std::int64_t now_ns, const Eigen::Quaterniond& attitude_world_body,
                           const std::array<Eigen::Vector3d, kTactileSensorCount>& pad_force_n) {
  if (now_ns < next_sample_ns_) return;
  next_sample_ns_ += period_ns_;
  if (config_.tactile_enabled) {
    for (int i = 0; i < kTactileSensorCount; ++i) {
      SampleNode(config_.tactile[i], tactile_states_[i], sequences_[i], pad_force_n[i],
                 attitude_world_body, now_ns);
    }
  }
  SampleNode(config_.reference, reference_state_, sequences_[kTactileSensorCount],
             Eigen::Vector3d::Zero(), attitude_world_body, now_ns);
}

}  // namespace hilrig::host
