#include "host/runner/imu_device.h"

#include <cmath>

#include "host/sensors/random_stream.h"

namespace hilrig::host {

ImuDevice::ImuDevice(const ImuParams& params, std::uint64_t seed)
    : params_(params),
      scales_(MakeImuNoiseScales(params)),
      state_(MakeImuState(
          params, RandomStream::FromSeed(seed, static_cast<std::uint64_t>(StreamId::kImu)))),
      period_ns_(std::llround(1e9 / params.rate_hz)) {}

// The schedule advances by whole periods from zero, so tick granularity never drifts the rate.
std::int64_t ImuDevice::Tick(std::int64_t now_ns, const PlantView& plant, DutPort& dut) {
  next_sample_ns_ += period_ns_;
  const ImuReading reading =
      SampleImu(params_, scales_, state_, plant.vehicle.body.angular_velocity_rad_s,
                plant.vehicle.specific_force_body_m_s2, now_ns);
  dut.Send(DutInput(std::in_place_type<ImuMessage>, LinkStamp{sequence_++, now_ns},
                    reading.gyro_rad_s, reading.accel_m_s2, reading.gyro_clipped,
                    reading.accel_clipped));
  gyro_clipped_samples_ += reading.gyro_clipped ? 1 : 0;
  accel_clipped_samples_ += reading.accel_clipped ? 1 : 0;
  return next_sample_ns_;
}

std::vector<rig::Metric> ImuDevice::metrics() const {
  return {rig::CountMetric("imu_gyro_clipped_samples", gyro_clipped_samples_),
          rig::CountMetric("imu_accel_clipped_samples", accel_clipped_samples_)};
}

}  // namespace hilrig::host
