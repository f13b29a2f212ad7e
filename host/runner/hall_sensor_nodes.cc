#include "host/runner/hall_sensor_nodes.h"

#include <algorithm>
#include <cmath>
#include <span>

#include "host/sensors/earth_field.h"
#include "host/sensors/tactile/memoized_film_field.h"
#include "rig/check.h"

namespace hilrig::host {
namespace {

// The reference node carries no film; it is given one it never reads.
class NoFilm final : public FilmFieldModel {
 public:
  Eigen::Vector3d FieldAtChip(const FilmPose&) const override { return Eigen::Vector3d::Zero(); }
};

// The silicone advances by one sample period per sample (the pad force held over it).
double SamplePeriodS(const dut_fw::SensorNode<>& firmware) {
  return 1.0 / std::max<double>(1, firmware.rate_hz());
}

}  // namespace

HallSensorNodes::HallSensorNodes(const HallSensorConfig& config, const EarthField& earth_field,
                                 std::uint64_t seed, std::shared_ptr<const FilmFieldModel> film,
                                 std::unique_ptr<rig::CanBus> bus)
    : config_(config),
      earth_field_(earth_field),
      film_(film ? std::shared_ptr<const FilmFieldModel>(
                       std::make_shared<const MemoizedFilmField>(std::move(film)))
                 : std::make_shared<const NoFilm>()),
      bus_(std::move(bus)) {
  dut_fw::NodeSettings settings;
  settings.rate_hz = static_cast<std::uint16_t>(std::lround(config.node_rate_hz));
  settings.chip = config.reference.chip.setting;
  const auto add = [&](const TactileSensorParams& params) {
    dut_fw::SensorNode<> firmware(params.node_id, 0, settings);
    auto stray_field_t = EventSchedule(
        config.stray_fields, [](const StrayFieldEvent& stray) { return stray.field_sensor_t; },
        [&](const StrayFieldEvent& stray) { return stray.node_id == params.node_id; });
    nodes_.push_back({&params, MakeTactileSensorConstants(params, SamplePeriodS(firmware)),
                      InitialTactileSensorState(params, seed), PadFieldMemo{}, firmware,
                      std::move(stray_field_t), FilmPose{}});
  };
  if (config.tactile_enabled) {
    for (const TactileSensorParams& params : config.tactile) add(params);
    if (config.film_cross_talk) {
      cross_talk_.emplace(MakeCrossTalkFarField(), config.tactile, config.reference);
    }
  }
  add(config.reference);
}

void HallSensorNodes::UpdateCrossTalk(
    const std::array<Eigen::Vector3d, kTactileSensorCount>* chip_position_body_m) {
  std::array<Eigen::Vector3d, kTactileSensorCount> chips;
  std::array<FilmPose, kTactileSensorCount> poses;
  for (int i = 0; i < kTactileSensorCount; ++i) {
    chips[i] =
        chip_position_body_m ? (*chip_position_body_m)[i] : config_.tactile[i].position_body_m;
    poses[i] = nodes_[i].film_pose;
  }
  cross_talk_->Update(chips, poses);
}

Eigen::Vector3d HallSensorNodes::FilmsFieldAt(std::size_t index) const {
  if (!cross_talk_) return Eigen::Vector3d::Zero();
  return index < kTactileSensorCount ? cross_talk_->AtTactileSensor(static_cast<int>(index))
                                     : cross_talk_->AtReferenceSensor();
}

// The frame is the one CanFrame::Classic(frame.id, payload) makes, written over the last one:
// its bytes past the node frame's eight stay zero, those from len to eight are cleared.
void HallSensorNodes::Send(const dut_fw::NodeFrame& frame, std::int64_t now_ns) {
  static_assert(sizeof(frame.data) == rig::CanFrame::kMaxClassicPayload);
  HILRIG_CHECK(frame.len <= frame.data.size(), "a node frame holds at most 8 bytes");
  can_frame_.id = frame.id;
  can_frame_.length = frame.len;
  std::copy(frame.data.begin(), frame.data.end(), can_frame_.data.begin());
  if (frame.len < frame.data.size()) [[unlikely]] {
    std::fill(can_frame_.data.begin() + frame.len, can_frame_.data.begin() + frame.data.size(), 0);
  }
  const auto sent = bus_->Send(can_frame_, now_ns);
  // A full or bus-off bus loses the frame, as on the wire; the DUT sees the sequence gap.
  (sent.ok() ? frames_sent_ : frames_dropped_)++;
}

void HallSensorNodes::TickNode(Node& node, const Eigen::Vector3d& pad_force_n,
                               const Eigen::Vector3d& earth_field_body_t,
                               const Eigen::Vector3d& films_field_t, std::int64_t now_ns) {
  if (node.firmware.SampleDue(now_ns)) {
    const double period_s = SamplePeriodS(node.firmware);
    if (period_s != node.constants.silicone.dt_s) {
      node.constants = MakeTactileSensorConstants(*node.params, period_s);
      node.pad_memo.Reset();
    }
    const TactileReading reading = SampleTactileSensor(
        *node.params, node.constants, node.model, *film_, pad_force_n, earth_field_body_t,
        config_.temperature_c,
        node.stray_field_t.At(static_cast<double>(now_ns) / 1e9) + films_field_t, &node.pad_memo);
    node.film_pose = reading.film_pose;
    Send(node.firmware.TakeSample(now_ns, dut_fw::ChipConversion{reading.code, false}), now_ns);
  }
  if (node.firmware.StatusDue(now_ns)) {
    node.firmware.OnTemperature(
        static_cast<std::int16_t>(std::lround(config_.temperature_c * 100)));
    Send(node.firmware.TakeStatus(now_ns), now_ns);
  }
}

std::uint64_t HallSensorNodes::stray_field_pieces_stepped() const {
  std::uint64_t stepped = 0;
  for (const Node& node : nodes_) stepped += node.stray_field_t.pieces_stepped();
  return stepped;
}

void HallSensorNodes::Tick(
    std::int64_t now_ns, const Eigen::Quaterniond& attitude_world_body,
    const std::array<Eigen::Vector3d, kTactileSensorCount>& pad_force_n,
    const std::array<Eigen::Vector3d, kTactileSensorCount>* chip_position_body_m) {
  // Only a node's own Take* calls move its schedule (the emulated nodes are sent no configuration
  // frames, the other thing that could), so nothing can fall due before this.
  if (now_ns < next_event_ns_) return;
  // The attitude's part of Earth's field, shared by every node on the vehicle.
  const Eigen::Vector3d earth_field_body_t =
      EarthFieldInBodyFrame(attitude_world_body, earth_field_.field_world_t);
  // Every node due now sees the films where their last samples left them.
  if (cross_talk_) UpdateCrossTalk(chip_position_body_m);
  std::int64_t next_event_ns = INT64_MAX;
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    // A node with nothing due (the others' slots, or a rate not dividing the tick) is skipped
    // without touching its inputs.
    Node& node = nodes_[i];
    if (node.firmware.SampleDue(now_ns) || node.firmware.StatusDue(now_ns)) {
      const bool tactile = config_.tactile_enabled && i < pad_force_n.size();
      TickNode(node, tactile ? pad_force_n[i] : Eigen::Vector3d::Zero(), earth_field_body_t,
               FilmsFieldAt(tactile ? i : kTactileSensorCount), now_ns);
    }
    next_event_ns = std::min(next_event_ns, node.firmware.NextEventNs());
  }
  next_event_ns_ = next_event_ns;
}

std::int64_t HallSensorNodes::Tick(std::int64_t now_ns, const PlantView& plant, DutPort&) {
  Tick(now_ns, plant.vehicle.body.orientation, plant.pad_force_n, plant.chip_position_body_m);
  return next_event_ns_;
}

std::vector<rig::Metric> HallSensorNodes::metrics() const {
  return {rig::CountMetric("hall_node_frames_sent", frames_sent_),
          rig::CountMetric("hall_node_frames_dropped", frames_dropped_)};
}

}  // namespace hilrig::host
