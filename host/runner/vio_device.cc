#include "host/runner/vio_device.h"

#include <algorithm>

#include "host/sensors/random_stream.h"

namespace hilrig::host {

VioDevice::VioDevice(const VioParams& params, std::uint64_t seed, bool airborne_at_start)
    : params_(params), airborne_at_start_(airborne_at_start) {
  state_.rng = RandomStream::FromSeed(seed, static_cast<std::uint64_t>(StreamId::kVio));
  delivered_.reserve(8);
}

std::int64_t VioDevice::Initialize(const PlantView& plant, DutPort& dut) {
  if (airborne_at_start_) {
    const RigidBodyState& body = plant.vehicle.body;
    dut.Send(VioMessage{{sequence_++, 0}, 0, body.position_m, body.orientation});
  }
  return NextEventNs();
}

std::int64_t VioDevice::Tick(std::int64_t now_ns, const PlantView& plant, DutPort& dut) {
  CaptureVio(params_, state_, plant.vehicle.body, now_ns);
  delivered_.clear();
  DeliverVio(state_, now_ns, delivered_);
  for (const VioPose& pose : delivered_) {
    dut.Send(
        VioMessage{{sequence_++, now_ns}, pose.capture_time_ns, pose.position_m, pose.orientation});
  }
  return NextEventNs();
}

std::int64_t VioDevice::NextEventNs() const {
  if (state_.in_flight.empty()) return state_.next_capture_ns;
  return std::min(state_.next_capture_ns, state_.in_flight.front().delivery_time_ns);
}

}  // namespace hilrig::host
