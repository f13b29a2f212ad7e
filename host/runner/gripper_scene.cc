#include "host/runner/gripper_scene.h"

#include <algorithm>
#include <cmath>

#include "host/sensors/tactile/silicone_model.h"
#include "rig/check.h"

namespace hilrig::host {
namespace {

// Where the mission expects contact: this far before the object's surface (its size known to
// about this much), so the first command of a grasp never lands inside the object. The force
// loop closes the last stretch at f_d / B_theta, about 10 mrad/s, so the margin is kept small.
constexpr double kApproachMarginM = 0.0005;

GraspSceneParams SceneFor(const ScenarioConfig& config, const TactileSensorParams& pad) {
  GraspSceneParams scene;
  scene.frame = config.gripper.frame;
  scene.pad_stiffness_n_per_m = SiliconeStiffness(pad.silicone);
  scene.pad_damping_n_s_per_m = SiliconeDamping(pad.silicone);
  scene.pad_stiffening_per_m2 =
      pad.silicone.stiffening_enabled ? pad.silicone.stiffening_per_m2 : 0.0;
  return scene;
}

}  // namespace

GripperScene::GripperScene(const ScenarioConfig& config,
                           const std::array<TactileSensorParams, kTactileSensorCount>& pads)
    : config_(config.gripper),
      scene_(SceneFor(config, pads[0])),
      gravity_m_s2_(config.vehicle.gravity_m_s2),
      pour_rate_kg_per_s_(EventSchedule(config.gripper.pours, [](const PourEvent& pour) {
        return pour.mass_kg / pour.duration_s;
      })) {
  HILRIG_CHECK(config_.enabled && !config_.objects.empty(), "a gripper scene needs an object");
  for (int i = 0; i < kTactileSensorCount; ++i) {
    body_from_pad_[i] = pads[i].mounting_body_from_sensor.toRotationMatrix();
  }
  servo_.angle_rad = config_.servo.min_angle_rad;
  UpdateChipPositions();
  Present(config_.objects[0]);
  next_object_ = 1;
}

void GripperScene::Present(const ObjectPlacement& placement) {
  if (next_object_ > 0) finished_.push_back(CurrentOutcome());
  scene_.object = placement.object;
  scene_.stand_height_m = placement.stand_height_m;
  scene_.stand_present = true;
  scene_constants_ = MakeGraspSceneConstants(scene_);
  grasp_ = InitialGraspState(scene_);
  current_ = proto::ObjectOutcome();
  current_.set_fixture(placement.fixture);
  damaged_at_s_ = -1;
}

GripperCommand GripperScene::CommandAt(double time_s) {
  // The latest event at or before time_s (grasps are in time order); the default reference angle
  // is worked out for that one only.
  const std::size_t passed = grasp_cursor_.Seek(
      time_s, config_.grasps.size(), [this](std::size_t i) { return config_.grasps[i].at_s; });
  GripperCommand command;
  if (passed == 0) return command;
  const GraspCommandEvent* latest = &config_.grasps[passed - 1];
  command.regulate = latest->regulate;
  command.force_n = latest->force_n;
  command.reference_angle_rad =
      latest->reference_angle_rad.has_value()
          ? *latest->reference_angle_rad
          : AngleForPadRadius(scene_.frame, scene_.object.half_width_m + kApproachMarginM);
  return command;
}

void GripperScene::Step(double time_s, double servo_command_rad, const QuadrotorState& vehicle,
                        double dt_s) {
  while (next_object_ < config_.objects.size() && config_.objects[next_object_].at_s <= time_s) {
    Present(config_.objects[next_object_]);
    ++next_object_;
  }
  while (next_support_removal_ < config_.support_removals_s.size() &&
         config_.support_removals_s[next_support_removal_] <= time_s) {
    scene_.stand_present = false;
    ++next_support_removal_;
  }
  if (!config_.pours.empty()) PourMass(grasp_, pour_rate_kg_per_s_.At(time_s) * dt_s);
  if (dt_s != servo_decay_dt_s_) {
    servo_decay_ = ServoLagDecay(config_.servo, dt_s);
    servo_decay_dt_s_ = dt_s;
  }
  servo_ = StepServoWithDecay(config_.servo, servo_, servo_command_rad,
                              GraspServoLoad(scene_, scene_constants_, grasp_), dt_s, servo_decay_);
  GraspVehicleSample sample;
  sample.position_m = vehicle.body.position_m;
  sample.orientation = vehicle.body.orientation;
  sample.specific_force_body_m_s2 = vehicle.specific_force_body_m_s2;
  sample.velocity_m_s = vehicle.body.velocity_m_s;
  sample.gravity_m_s2 = gravity_m_s2_;
  StepGrasp(scene_, scene_constants_, grasp_, sample, servo_.angle_rad, dt_s, forces_);
  UpdateChipPositions();
  if (grasp_.damage != DamageMode::kNone && damaged_at_s_ < 0) {
    damaged_at_s_ = time_s;
    any_damaged_ = true;
  }
  if (grasp_.mode == GraspMode::kDropped) any_dropped_ = true;
  // NaN must show, not vanish in std::max.
  peak_elastic_energy_j_ = std::isnan(forces_.elastic_energy_j)
                               ? forces_.elastic_energy_j
                               : std::max(peak_elastic_energy_j_, forces_.elastic_energy_j);
  for (const Eigen::Vector3d& pad_force_n : forces_.pad_force_n) {
    const double squared_n2 = pad_force_n.squaredNorm();
    peak_pad_force_squared_n2_ =
        std::isnan(squared_n2) ? squared_n2 : std::max(peak_pad_force_squared_n2_, squared_n2);
  }
  if (forces_.released_pads > 0) {
    ++pad_release_ticks_;
    unbalanced_horizontal_max_n_ =
        std::max(unbalanced_horizontal_max_n_, forces_.unbalanced_horizontal_n);
  }
}

void GripperScene::UpdateChipPositions() {
  if (servo_.angle_rad == chip_positions_angle_rad_) return;
  chip_positions_angle_rad_ = servo_.angle_rad;
  for (int pad = 0; pad < kTactileSensorCount; ++pad) {
    chip_position_body_m_[pad] = ChipPositionBody(scene_.frame, pad, servo_.angle_rad);
  }
}

double GripperScene::elastic_energy_bound_j() const {
  return config_.servo.stall_torque_nm *
         (config_.servo.max_angle_rad - config_.servo.min_angle_rad);
}

Eigen::Vector3d GripperScene::ContactForceWorld(const Eigen::Quaterniond& attitude) const {
  Eigen::Vector3d body_n = Eigen::Vector3d::Zero();
  for (int i = 0; i < kTactileSensorCount; ++i)
    body_n += body_from_pad_[i] * forces_.pad_force_n[i];
  return attitude * body_n;
}

std::vector<proto::ObjectOutcome> GripperScene::Outcomes() const {
  std::vector<proto::ObjectOutcome> outcomes = finished_;
  outcomes.push_back(CurrentOutcome());
  return outcomes;
}

proto::ObjectOutcome GripperScene::CurrentOutcome() const {
  proto::ObjectOutcome current = current_;
  const double limit_n = scene_.object.damage_force_n;
  if (scene_.object.damage_mode != DamageMode::kNone && std::isfinite(limit_n)) {
    current.set_damage_force_n(limit_n);
    current.set_damage_margin_n(limit_n - grasp_.peak_normal_force_n);
  }
  current.set_damage(DamageModeName(grasp_.damage));
  if (damaged_at_s_ >= 0) current.set_damaged_at_s(damaged_at_s_);
  current.set_final_state(GraspModeName(grasp_.mode));
  current.set_peak_normal_force_n(grasp_.peak_normal_force_n);
  current.set_peak_indentation_m(grasp_.peak_indentation_m);
  return current;
}

std::uint64_t GripperScene::timeline_entries_stepped() const {
  return next_object_ + next_support_removal_ + grasp_cursor_.steps() +
         pour_rate_kg_per_s_.pieces_stepped();
}

}  // namespace hilrig::host
