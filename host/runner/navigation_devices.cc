#include "host/runner/navigation_devices.h"

#include <cmath>

namespace hilrig::host {

PeriodicSensorDevice::PeriodicSensorDevice(double rate_hz, std::uint64_t seed, StreamId stream)
    : rng_(RandomStream::FromSeed(seed, stream)), period_ns_(std::llround(1e9 / rate_hz)) {}

std::int64_t PeriodicSensorDevice::Tick(std::int64_t now_ns, const PlantView& plant, DutPort& dut) {
  next_sample_ns_ += period_ns_;
  dut.Send(Sample(LinkStamp{sequence_++, now_ns}, plant));
  return next_sample_ns_;
}

MagnetometerDevice::MagnetometerDevice(const MagnetometerParams& params,
                                       const EarthField& earth_field, std::uint64_t seed)
    : PeriodicSensorDevice(params.rate_hz, seed, StreamId::kMagnetometer),
      params_(params),
      earth_field_(earth_field) {}

DutInput MagnetometerDevice::Sample(const LinkStamp& stamp, const PlantView& plant) {
  return MagnetometerMessage{stamp, SampleMagnetometer(params_, plant.vehicle.body.orientation,
                                                       earth_field_.field_world_t, rng())};
}

BarometerDevice::BarometerDevice(const NavigationSensorsConfig& config, std::uint64_t seed)
    : PeriodicSensorDevice(config.barometer.rate_hz, seed, StreamId::kBarometer), config_(config) {}

DutInput BarometerDevice::Sample(const LinkStamp& stamp, const PlantView& plant) {
  const double altitude_m = config_.origin.altitude_m + plant.vehicle.body.position_m.z();
  const BarometerReading reading = SampleBarometer(config_.barometer, altitude_m, rng());
  return BarometerMessage{stamp, reading.pressure_pa, reading.temperature_c};
}

GnssDevice::GnssDevice(const NavigationSensorsConfig& config, std::uint64_t seed)
    : PeriodicSensorDevice(config.gnss.rate_hz, seed, StreamId::kGnss), config_(config) {}

DutInput GnssDevice::Sample(const LinkStamp& stamp, const PlantView& plant) {
  const RigidBodyState& body = plant.vehicle.body;
  const GnssReading reading =
      SampleGnss(config_.gnss, config_.origin, body.position_m, body.velocity_m_s, rng());
  return GnssMessage{stamp,
                     reading.position.latitude_deg,
                     reading.position.longitude_deg,
                     reading.position.altitude_m,
                     reading.velocity_m_s,
                     reading.horizontal_accuracy_m,
                     reading.vertical_accuracy_m,
                     static_cast<std::uint8_t>(config_.gnss.satellites)};
}

std::vector<std::unique_ptr<DeviceEmulator>> MakeNavigationDevices(
    const NavigationSensorsConfig& config, const EarthField& earth_field, std::uint64_t seed) {
  std::vector<std::unique_ptr<DeviceEmulator>> devices;
  devices.push_back(std::make_unique<MagnetometerDevice>(config.magnetometer, earth_field, seed));
  devices.push_back(std::make_unique<BarometerDevice>(config, seed));
  devices.push_back(std::make_unique<GnssDevice>(config, seed));
  return devices;
}

}  // namespace hilrig::host
