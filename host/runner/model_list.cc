#include "host/runner/model_list.h"

#include <sstream>

namespace hilrig::host {
namespace {

void Add(proto::Report& report, const std::string& name, const std::string& fidelity) {
  proto::ModelInfo* model = report.add_models();
  model->set_name(name);
  model->set_fidelity(fidelity);
}

template <typename... Parts>
std::string Describe(const Parts&... parts) {
  std::ostringstream text;
  (text << ... << parts);
  return text.str();
}

}  // namespace

void AppendModelList(const ScenarioConfig& config, const std::string& dut_description,
                     proto::Report& report) {
  const bool rk4 = config.vehicle.integrator == Integrator::kRk4;
  Add(report, "vehicle",
      Describe("full 6-DoF rigid body, ", config.vehicle.body.mass_kg, " kg, ",
               rk4 ? "RK4" : "semi-implicit Euler", " at ", 1e9 / config.physics_step_ns,
               " Hz, flat ground"));
  Add(report, "rotors",
      config.vehicle.rotors.instantaneous
          ? std::string("instantaneous thrust")
          : Describe("first-order lag, tau ", config.vehicle.rotors.time_constant_s, " s"));
  const char* noise = config.imu.noise_enabled ? "noise on" : "noise off";
  Add(report, "imu", Describe(config.imu.rate_hz, " Hz, ", noise));
  Add(report, "vio",
      Describe(config.vio.rate_hz, " Hz, latency ", config.vio.latency_s, " s, ", noise));
  Add(report, "reference_magnetometer",
      Describe("Earth field rotated by attitude, MLX90393 LSB quantization, ",
               config.magnetometer.rate_hz, " Hz, ", noise));
  Add(report, "can_bus", Describe("emulated, ", config.can_bitrate_bps / 1e3, " kbit/s"));
  Add(report, "dut", dut_description);
}

}  // namespace hilrig::host
