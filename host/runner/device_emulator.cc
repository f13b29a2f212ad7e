#include "host/runner/device_emulator.h"

#include <algorithm>

namespace hilrig::host {

std::int64_t DeviceEmulator::Initialize(const PlantView&, DutPort&) { return 0; }

void DeviceSchedule::Add(DeviceEmulator& device) {
  devices_.push_back(&device);
  entries_.push_back({&device, std::numeric_limits<std::int64_t>::max()});
}

void DeviceSchedule::Initialize(const PlantView& plant, DutPort& dut) {
  earliest_event_ns_ = std::numeric_limits<std::int64_t>::max();
  for (Entry& entry : entries_) {
    entry.next_event_ns = entry.device->Initialize(plant, dut);
    earliest_event_ns_ = std::min(earliest_event_ns_, entry.next_event_ns);
  }
}

void DeviceSchedule::TickDue(std::int64_t now_ns, const PlantView& plant, DutPort& dut) {
  std::int64_t earliest_ns = std::numeric_limits<std::int64_t>::max();
  for (Entry& entry : entries_) {
    if (now_ns >= entry.next_event_ns) entry.next_event_ns = entry.device->Tick(now_ns, plant, dut);
    earliest_ns = std::min(earliest_ns, entry.next_event_ns);
  }
  earliest_event_ns_ = earliest_ns;
}

}  // namespace hilrig::host
