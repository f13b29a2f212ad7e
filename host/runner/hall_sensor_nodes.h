// The seven Hall sensor nodes as devices on the CAN bus: at every node period each node samples
// its forward model (pad force -> silicone -> film field, plus Earth's field rotated by the
// vehicle's attitude, through the MLX90393 model) and sends one frame with its raw result words,
// its sequence counter and its saturation status. The DUT sees only these frames.
#pragma once

#include <array>
#include <memory>

#include "host/scenario/scenario_config.h"
#include "host/sensors/tactile/film_field.h"
#include "rig/can_bus.h"

namespace hilrig::host {

class HallSensorNodes {
 public:
  // `film` may be null when the tactile nodes are off (the reference node needs no film).
  HallSensorNodes(const HallSensorConfig& config, const EarthField& earth_field, std::uint64_t seed,
                  std::shared_ptr<const FilmFieldModel> film, std::unique_ptr<rig::CanBus> bus);

  // Samples every node and sends its frame when a node period is due at `now_ns`.
  void Tick(std::int64_t now_ns, const Eigen::Quaterniond& attitude_world_body,
            const std::array<Eigen::Vector3d, kTactileSensorCount>& pad_force_n);

  std::uint64_t frames_sent() const { return frames_sent_; }
  std::uint64_t frames_dropped() const { return frames_dropped_; }

 private:
  void SampleNode(const TactileSensorParams& params, TactileSensorState& state,
                  std::uint8_t& sequence, const Eigen::Vector3d& pad_force_n,
                  const Eigen::Quaterniond& attitude_world_body, std::int64_t now_ns);

  const HallSensorConfig& config_;
  const EarthField& earth_field_;
  std::shared_ptr<const FilmFieldModel> film_;
  std::unique_ptr<rig::CanBus> bus_;
  std::array<TactileSensorState, kTactileSensorCount> tactile_states_;
  TactileSensorState reference_state_;
  std::array<std::uint8_t, kTactileSensorCount + 1> sequences_{};
  std::int64_t period_ns_;
  std::int64_t next_sample_ns_ = 0;
  std::uint64_t frames_sent_ = 0;
  std::uint64_t frames_dropped_ = 0;
};

}  // namespace hilrig::host
