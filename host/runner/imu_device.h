// The IMU as a device: one gyro and accelerometer reading per IMU period (host/sensors/
// imu_emulator.h), sent to the DUT as an ImuMessage stamped with the tick it was taken at, with
// the flags of the axes that hit their full scale.
#pragma once

#include <cstdint>

#include "host/runner/device_emulator.h"
#include "host/sensors/imu_emulator.h"

namespace hilrig::host {

class ImuDevice final : public DeviceEmulator {
 public:
  // `params` must outlive the device; its noise draws from the scene seed's IMU stream.
  ImuDevice(const ImuParams& params, std::uint64_t seed);

  std::int64_t Tick(std::int64_t now_ns, const PlantView& plant, DutPort& dut) override;
  // How many readings had an axis at its full scale (imu_gyro_clipped_samples,
  // imu_accel_clipped_samples): a touchdown or a crash shows there.
  std::vector<rig::Metric> metrics() const override;

 private:
  const ImuParams& params_;
  const ImuNoiseScales scales_;
  ImuState state_;
  std::int64_t period_ns_;
  std::int64_t next_sample_ns_ = 0;
  std::uint64_t sequence_ = 0;
  std::uint64_t gyro_clipped_samples_ = 0;
  std::uint64_t accel_clipped_samples_ = 0;
};

}  // namespace hilrig::host
