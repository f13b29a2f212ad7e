// The navigation sensors a flight stack fuses (host/sensors/navigation_sensors.h) as devices: a
// magnetometer, a barometer and a GNSS receiver, each sampling the plant on its own period from
// time 0 and sending the DUT one message per sample. The runner builds them only for a DUT that
// takes them (DutPort::TakesNavigationSensors): the rig's own controller takes none, and a scene
// models only what its DUT hears.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "host/runner/device_emulator.h"
#include "host/sensors/earth_field.h"
#include "host/sensors/navigation_sensors.h"
#include "host/sensors/random_stream.h"

namespace hilrig::host {

// A sensor sampled every period on a grid from time 0 (no drift), its readings drawing on one
// random stream of the scene's seed.
class PeriodicSensorDevice : public DeviceEmulator {
 public:
  std::int64_t Tick(std::int64_t now_ns, const PlantView& plant, DutPort& dut) final;

 protected:
  PeriodicSensorDevice(double rate_hz, std::uint64_t seed, StreamId stream);
  // The reading at `now_ns`, stamped with `stamp`.
  virtual DutInput Sample(const LinkStamp& stamp, const PlantView& plant) = 0;
  RandomStream& rng() { return rng_; }

 private:
  RandomStream rng_;
  std::int64_t period_ns_;
  std::int64_t next_sample_ns_ = 0;
  std::uint64_t sequence_ = 0;
};

// Earth's field rotated into the body, plus the vehicle's stray field and noise.
class MagnetometerDevice final : public PeriodicSensorDevice {
 public:
  // `params` and `earth_field` must outlive the device.
  MagnetometerDevice(const MagnetometerParams& params, const EarthField& earth_field,
                     std::uint64_t seed);

 private:
  DutInput Sample(const LinkStamp& stamp, const PlantView& plant) override;
  const MagnetometerParams& params_;
  const EarthField& earth_field_;
};

// The standard atmosphere at the vehicle's altitude above mean sea level.
class BarometerDevice final : public PeriodicSensorDevice {
 public:
  // `config` must outlive the device.
  BarometerDevice(const NavigationSensorsConfig& config, std::uint64_t seed);

 private:
  DutInput Sample(const LinkStamp& stamp, const PlantView& plant) override;
  const NavigationSensorsConfig& config_;
};

// The vehicle's position as latitude, longitude and altitude from the scene's geodetic origin,
// and its velocity.
class GnssDevice final : public PeriodicSensorDevice {
 public:
  // `config` must outlive the device.
  GnssDevice(const NavigationSensorsConfig& config, std::uint64_t seed);

 private:
  DutInput Sample(const LinkStamp& stamp, const PlantView& plant) override;
  const NavigationSensorsConfig& config_;
};

// The three, in the order they tick. `config` and `earth_field` must outlive them.
std::vector<std::unique_ptr<DeviceEmulator>> MakeNavigationDevices(
    const NavigationSensorsConfig& config, const EarthField& earth_field, std::uint64_t seed);

}  // namespace hilrig::host
