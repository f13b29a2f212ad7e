#include "host/runner/scene_devices.h"

#include "host/runner/hall_sensor_nodes.h"
#include "host/runner/imu_device.h"
#include "host/runner/vio_device.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "rig/check.h"

namespace hilrig::host {
namespace {

std::shared_ptr<const FilmFieldModel> FilmFieldFor(const ScenarioConfig& config) {
  if (!config.hall_sensors.tactile_enabled) return nullptr;
  if (config.hall_sensors.film_field != nullptr) return config.hall_sensors.film_field;
  auto film = MakeFilmField(config.hall_sensors.field_fidelity);
  HILRIG_CHECK(film.ok(), "the spec's field fidelity was validated before the run");
  return film.value();
}

}  // namespace

std::vector<std::unique_ptr<DeviceEmulator>> MakeSceneDevices(const ScenarioConfig& config,
                                                              rig::EmulatedBus& bus) {
  std::vector<std::unique_ptr<DeviceEmulator>> devices;
  devices.push_back(std::make_unique<ImuDevice>(config.imu, config.seed));
  // The vehicle starts where its reference starts: in the air, hovering.
  devices.push_back(std::make_unique<VioDevice>(config.vio, config.seed,
                                                config.initial_reference.position_m.z() > 0));
  devices.push_back(std::make_unique<HallSensorNodes>(config.hall_sensors, config.earth_field,
                                                      config.seed, FilmFieldFor(config),
                                                      bus.Connect("hall-sensor-nodes")));
  return devices;
}

}  // namespace hilrig::host
