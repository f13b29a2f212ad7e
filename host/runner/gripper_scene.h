// The grasp side of a scene, as the runner steps it: the servo that shrinks the frame, the pads
// against the current object (contact, friction, slip, the stand, damage), the objects the
// timeline puts on the stand, and the scripted mass flows poured into them. Each tick it takes the
// DUT's servo command and the vehicle as it is, and leaves behind the pad forces the Hall sensor
// nodes read next, the force and payload the vehicle step takes, and what the trace and report
// show. The models are host/plant (servo, gripper_frame, grasp_contact); this class only
// sequences them and resolves the timeline, so it holds no physics of its own.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "host/plant/grasp_contact.h"
#include "host/plant/quadrotor.h"
#include "host/plant/servo.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/timeline_schedule.h"
#include "proto/report.pb.h"

namespace hilrig::host {

// What the mission asks of the gripper at a given time.
struct GripperCommand {
  bool regulate = false;
  double force_n = 0;
  double reference_angle_rad = 0;
};

class GripperScene {
 public:
  // `config.gripper.enabled` must be true; `pads` gives the pads' silicone and mountings.
  GripperScene(const ScenarioConfig& config,
               const std::array<TactileSensorParams, kTactileSensorCount>& pads);

  // The grasp command in force at `time_s` (the latest timeline grasp at or before it). Times that
  // do not decrease cost O(1) amortised, however many grasps the timeline has.
  GripperCommand CommandAt(double time_s);

  // One physics tick: objects due are put on the stand, pours add mass, the servo moves toward
  // `servo_command_rad` against the grasp's load and the contact is solved for the vehicle's state.
  void Step(double time_s, double servo_command_rad, const QuadrotorState& vehicle, double dt_s);

  const GraspForces& forces() const { return forces_; }
  // What the vehicle step carries of the object this tick (nothing unless it is held).
  Payload payload() const { return {forces_.payload_mass_kg, forces_.payload_inertia_kg_m2}; }
  const GraspState& grasp() const { return grasp_; }
  const ServoState& servo() const { return servo_; }
  const GraspSceneParams& scene() const { return scene_; }
  const std::array<Eigen::Vector3d, kTactileSensorCount>& pad_forces() const {
    return forces_.pad_force_n;
  }
  // The Hall chips where the frame's angle puts them (ChipPositionBody), body frame.
  const std::array<Eigen::Vector3d, kTactileSensorCount>& chip_positions() const {
    return chip_position_body_m_;
  }
  // The contacts' force on the vehicle in the world frame, summed from the pad forces: what ideal
  // pads would tell the DUT. Includes the held object's share that the vehicle step carries as
  // payload mass.
  Eigen::Vector3d ContactForceWorld(const Eigen::Quaterniond& attitude) const;
  // Has any object been damaged / dropped so far.
  bool any_damaged() const { return any_damaged_; }
  bool any_dropped() const { return any_dropped_; }
  // Is an object on the pads now (held or sliding), so that the vehicle's motion reaches it.
  bool holds_object() const {
    return grasp_.mode == GraspMode::kHeld || grasp_.mode == GraspMode::kSliding;
  }
  // Largest elastic energy stored in pads and object so far, and the bound physics puts on it: the
  // servo cannot do more work on the grasp than its stall torque over its whole range.
  double peak_elastic_energy_j() const { return peak_elastic_energy_j_; }
  // Largest force (normal and shear together) any pad's film has felt so far: the physics step,
  // not the 100 Hz trace, sees a touch-down's short peak.
  double peak_pad_force_n() const { return std::sqrt(peak_pad_force_squared_n2_); }
  double elastic_energy_bound_j() const;
  // Ticks in which holding the object horizontally released a pad (it would have had to pull),
  // and the largest horizontal force the pads then left unapplied (0 while the pads in contact
  // balance the hold, as they do for any grip that holds the object).
  std::uint64_t pad_release_ticks() const { return pad_release_ticks_; }
  double unbalanced_horizontal_max_n() const { return unbalanced_horizontal_max_n_; }

  // One outcome per object presented so far (the current one as it is now).
  std::vector<proto::ObjectOutcome> Outcomes() const;

  // Timeline entries (grasps, objects, support removals, pour schedule pieces) stepped over so
  // far: each at most once over a run, however many ticks it has.
  std::uint64_t timeline_entries_stepped() const;

 private:
  void Present(const ObjectPlacement& placement);
  // Moves the chips to the servo's angle; nothing to do while the angle stays where it was (the
  // tick calls it every time, and the frame is still most of a run).
  void UpdateChipPositions();
  proto::ObjectOutcome CurrentOutcome() const;

  const GripperConfig& config_;
  std::array<Eigen::Matrix3d, kTactileSensorCount> body_from_pad_;
  GraspSceneParams scene_;
  // Derived from scene_ alone; recomputed whenever Present() changes the object (the stand's
  // removal does not enter it), so the tick does not re-derive it.
  GraspSceneConstants scene_constants_;
  double gravity_m_s2_;
  GraspState grasp_;
  ServoState servo_;
  // The servo's lag decay for the dt it was computed for: the runner's dt is fixed, so exp() runs
  // once per run instead of once per tick.
  double servo_decay_dt_s_ = -1;
  double servo_decay_ = 0;
  GraspForces forces_;
  std::array<Eigen::Vector3d, kTactileSensorCount> chip_position_body_m_;
  double chip_positions_angle_rad_ = std::numeric_limits<double>::quiet_NaN();  // they are at
  std::size_t next_object_ = 0;
  std::size_t next_support_removal_ = 0;
  TimeCursor grasp_cursor_;
  IntervalSumSchedule<double> pour_rate_kg_per_s_;
  std::vector<proto::ObjectOutcome> finished_;
  proto::ObjectOutcome current_;
  double damaged_at_s_ = -1;
  bool any_damaged_ = false;
  bool any_dropped_ = false;
  double peak_elastic_energy_j_ = 0;
  double peak_pad_force_squared_n2_ = 0;  // squared, so the tick takes no square roots
  std::uint64_t pad_release_ticks_ = 0;
  double unbalanced_horizontal_max_n_ = 0;
};

}  // namespace hilrig::host
