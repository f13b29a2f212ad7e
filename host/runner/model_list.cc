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

const char* VehicleFidelityName(VehicleFidelity fidelity) {
  switch (fidelity) {
    case VehicleFidelity::kVertical1Dof:
      return "vertical 1-DoF (altitude only, level, no rotation)";
    case VehicleFidelity::kFixedStand:
      return "fixed stand (nothing moves; rotors and sensors run)";
    case VehicleFidelity::kFull6Dof:
      break;
  }
  return "full 6-DoF rigid body";
}

}  // namespace

void AppendModelList(const ScenarioConfig& config, const std::string& dut_description,
                     proto::Report& report) {
  const QuadrotorParams& vehicle = config.vehicle;
  const std::string tolerance = vehicle.integrator == Integrator::kDormandPrince
                                    ? Describe(" (tolerance ", vehicle.integrator_tolerance, ")")
                                    : std::string();
  Add(report, "vehicle",
      Describe(VehicleFidelityName(vehicle.fidelity), ", ", vehicle.body.mass_kg, " kg, ",
               IntegratorName(vehicle.integrator), tolerance, " at ", 1e9 / config.physics_step_ns,
               " Hz",
               config.plant_substeps > 1 ? Describe(" x ", config.plant_substeps, " substeps")
                                         : std::string(),
               ", flat ground"));
  Add(report, "rotors",
      config.vehicle.rotors.instantaneous
          ? std::string("instantaneous thrust")
          : Describe("first-order lag, tau ", config.vehicle.rotors.time_constant_s, " s"));
  const char* noise = config.imu.noise_enabled ? "noise on" : "noise off";
  Add(report, "imu", Describe(config.imu.rate_hz, " Hz, ", noise));
  Add(report, "vio",
      Describe(config.vio.rate_hz, " Hz, latency ", config.vio.latency_s, " s, ", noise));
  const HallSensorConfig& hall = config.hall_sensors;
  const TactileSensorParams& chip_owner = hall.reference;
  const std::string chip = Describe(
      "MLX90393 GAIN_SEL ", int{chip_owner.chip.setting.gain_sel}, " RES ",
      int{chip_owner.chip.setting.resolution}, chip_owner.chip.noise_enabled ? ", noise" : "",
      chip_owner.chip.drift_enabled ? ", drift" : "",
      chip_owner.chip.saturation_enabled ? ", saturation" : "",
      chip_owner.earth_field_enabled ? ", Earth field rotated by attitude" : ", no Earth field");
  Add(report, "reference_magnetometer", Describe("node 7, ", chip, ", ", hall.node_rate_hz, " Hz"));
  if (hall.tactile_enabled) {
    const SiliconeParams& silicone = hall.tactile[0].silicone;
    Add(report, "tactile_pads",
        Describe("nodes 1-6, film field ", hall.field_fidelity, ", silicone",
                 silicone.damping_enabled ? " damped" : "",
                 silicone.stiffening_enabled ? " stiffening" : " linear", ", ", chip,
                 hall.compensation ? "; DUT compensates" : "; DUT does not compensate"));
  }
  if (config.gripper.enabled) {
    const ServoParams& servo = config.gripper.servo;
    Add(report, "gripper_servo",
        Describe("own position loop, tau ", servo.time_constant_s, " s, ", servo.max_rate_rad_s,
                 " rad/s, stall ", servo.stall_torque_nm, " N m; frame shrinks ",
                 config.gripper.frame.closing_m_per_rad * 1e3, " mm/rad"));
    std::string objects;
    for (const ObjectPlacement& placement : config.gripper.objects) {
      objects += (objects.empty() ? "" : ", ") + placement.fixture;
    }
    Add(report, "grasp_contact",
        Describe("quasi-static pad and object compliance in series, Coulomb friction with stick "
                 "and slip, stand, damage criteria; objects: ",
                 objects));
  }
  Add(report, "can_bus", Describe("emulated, ", config.can_bitrate_bps / 1e3, " kbit/s"));
  Add(report, "dut", dut_description);
}

}  // namespace hilrig::host
