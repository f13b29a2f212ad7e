#include "host/runner/device_emulator.h"

#include <algorithm>

namespace hilrig::host {

std::int64_t DeviceEmulator::Initialize(const PlantView&, DutPort&) { return 0; }

void DeviceSchedule::Add(DeviceEmulator& device) {
  devices_.push_back(&device);
  next_event_ns_.push_back(std::numeric_limits<std::int64_t>::max());
}

void DeviceSchedule::Initialize(const PlantView& plant, DutPort& dut) {
  earliest_event_ns_ = std::numeric_limits<std::int64_t>::max();
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    next_event_ns_[i] = devices_[i]->Initialize(plant, dut);
    earliest_event_ns_ = std::min(earliest_event_ns_, next_event_ns_[i]);
  }
}

void DeviceSchedule::TickDue(std::int64_t now_ns, const PlantView& plant, DutPort& dut) {
  std::int64_t earliest_ns = std::numeric_limits<std::int64_t>::max();
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    if (now_ns >= next_event_ns_[i]) next_event_ns_[i] = devices_[i]->Tick(now_ns, plant, dut);
    earliest_ns = std::min(earliest_ns, next_event_ns_[i]);
  }
  earliest_event_ns_ = earliest_ns;
}

}  // namespace hilrig::host
