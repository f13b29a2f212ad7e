// The VIO as a device: captures a noisy pose at the VIO frame rate and delivers it to the DUT one
// processing latency later (host/sensors/vio_emulator.h). A vehicle that starts in the air has
// been flying, so its DUT is told where it is before the first tick.
#pragma once

#include <cstdint>
#include <vector>

#include "host/runner/device_emulator.h"
#include "host/sensors/vio_emulator.h"

namespace hilrig::host {

class VioDevice final : public DeviceEmulator {
 public:
  // `params` must outlive the device; its noise draws from the scene seed's VIO stream.
  VioDevice(const VioParams& params, std::uint64_t seed, bool airborne_at_start);

  std::int64_t Initialize(const PlantView& plant, DutPort& dut) override;
  std::int64_t Tick(std::int64_t now_ns, const PlantView& plant, DutPort& dut) override;

 private:
  // The next capture or the next delivery, whichever comes first.
  std::int64_t NextEventNs() const;

  const VioParams& params_;
  VioState state_;
  bool airborne_at_start_;
  std::uint64_t sequence_ = 0;
  std::vector<VioPose> delivered_;  // reused by every tick
};

}  // namespace hilrig::host
