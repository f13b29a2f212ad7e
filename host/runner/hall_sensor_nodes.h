// The seven Hall sensor nodes as devices on the CAN bus. Each node runs the node firmware
// (dut_fw/sensor_node.h: sampling schedule, frame packing, sequence, status frames) on top of its
// forward model (pad force -> silicone -> film field, plus Earth's field rotated by the vehicle's
// attitude, through the MLX90393 model): the chip model answers the firmware's conversions, and
// the firmware's frames go on the bus (proto/TACTILE_PROTOCOL.md). The DUT sees only these frames:
// as a device they send on the bus endpoint they were built with, never through the DUT port.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "dut_fw/sensor_node.h"
#include "host/runner/device_emulator.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/timeline_schedule.h"
#include "host/sensors/tactile/film_cross_talk.h"
#include "host/sensors/tactile/film_field.h"
#include "host/sensors/tactile/tactile_sensor.h"
#include "rig/can_bus.h"
#include "rig/can_frame.h"

namespace hilrig::host {

class HallSensorNodes final : public DeviceEmulator {
 public:
  // `film` may be null when the tactile nodes are off (the reference node needs no film).
  HallSensorNodes(const HallSensorConfig& config, const EarthField& earth_field, std::uint64_t seed,
                  std::shared_ptr<const FilmFieldModel> film, std::unique_ptr<rig::CanBus> bus);

  // Runs every node's firmware at `now_ns`: samples and status frames that are due go out. Stray
  // fields of the timeline (config.stray_fields) are added at their nodes while they last, and
  // with config.film_cross_talk the films' fields at each other's chips and at the reference
  // (film_cross_talk.h), from the films' poses at their last samples and the chips at
  // `chip_position_body_m` (null: where the layout puts them).
  void Tick(std::int64_t now_ns, const Eigen::Quaterniond& attitude_world_body,
            const std::array<Eigen::Vector3d, kTactileSensorCount>& pad_force_n,
            const std::array<Eigen::Vector3d, kTactileSensorCount>* chip_position_body_m = nullptr);
  // The same, as a device: the vehicle's attitude and the pad forces from the plant's view.
  std::int64_t Tick(std::int64_t now_ns, const PlantView& plant, DutPort& dut) override;
  // "hall_node_frames_sent", "hall_node_frames_dropped".
  std::vector<rig::Metric> metrics() const override;
  std::uint64_t timeline_entries_stepped() const override { return stray_field_pieces_stepped(); }

  std::uint64_t frames_sent() const { return frames_sent_; }
  // Frames the bus refused (full TX queue, bus-off); the DUT sees them as sequence gaps.
  std::uint64_t frames_dropped() const { return frames_dropped_; }
  // Pieces of the nodes' stray-field schedules stepped over so far: each at most once over a run.
  std::uint64_t stray_field_pieces_stepped() const;

 private:
  struct Node {
    const TactileSensorParams* params;
    TactileSensorConstants constants;  // for the firmware's current sample period
    TactileSensorState model;
    PadFieldMemo pad_memo;  // of params, constants and film_; reset with the constants
    dut_fw::SensorNode<> firmware;
    IntervalSumSchedule<Eigen::Vector3d> stray_field_t;  // the timeline's, at this node
    FilmPose film_pose;  // at the last sample (the reference node's stays at rest, unused)
  };

  void TickNode(Node& node, const Eigen::Vector3d& pad_force_n,
                const Eigen::Vector3d& earth_field_body_t, const Eigen::Vector3d& films_field_t,
                std::int64_t now_ns);
  // The films' fields at node `index` (sensor frame): zero without cross-talk.
  Eigen::Vector3d FilmsFieldAt(std::size_t index) const;
  void UpdateCrossTalk(
      const std::array<Eigen::Vector3d, kTactileSensorCount>* chip_position_body_m);
  void Send(const dut_fw::NodeFrame& frame, std::int64_t now_ns);

  const HallSensorConfig& config_;
  const EarthField& earth_field_;
  std::shared_ptr<const FilmFieldModel> film_;
  std::unique_ptr<rig::CanBus> bus_;
  std::vector<Node> nodes_;                  // the tactile ones (when enabled), then the reference
  std::optional<FilmCrossTalk> cross_talk_;  // with tactile nodes and config.film_cross_talk
  rig::CanFrame can_frame_;  // the frame being sent, reused so it is not built from zero each time
  std::uint64_t frames_sent_ = 0;
  std::uint64_t frames_dropped_ = 0;
  // The earliest NextEventNs of the nodes: at the 1 kHz tick and 50 Hz samples a Tick before it
  // has nothing to do in 19 of 20 ticks.
  std::int64_t next_event_ns_ = INT64_MIN;
};

}  // namespace hilrig::host
