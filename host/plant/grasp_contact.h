// The six pads against one object: normal forces, friction, slip, the stand the object starts on,
// lifting it, dropping it and breaking it. This is what turns the frame angle and the vehicle's
// motion into the forces on each tactile pad's film, the load on the servo and the force the
// grasp puts on the vehicle.
//
// Quasi-static contact. The pad/object contact modes ring far above 100 Hz, well beyond anything
// the controllers do, so nothing stiff is integrated. The object's centre sits on the frame
// centre horizontally (the pads centre it), and the scene assumes the frame is around the object
// whenever the frame angle makes the pads reach it. At angle a every pad overlaps the object by
// half_width - PadSurfaceRadius(a); the pad (normal F = k_n d (1 + beta d^2)) and the object
// (F = k d^n (1 + (d / L)^2)) are springs in series, solved algebraically for pad compression d_p
// and object indentation d_o with d_p + d_o = overlap and equal force (closed form when both are
// linear, otherwise a bracketed, safeguarded Newton in d_o). The servo moves toward the angle where
// its torque equals closing_m_per_rad times the sum of the normal forces (servo.h), so any object
// stiffness is stable by construction. The only integrated relative motion is sliding, driven by
// bounded friction.
//
// Modes. Body z (the pads' y_S) is the sliding direction; "frame height" is the world z of the
// frame centre (body origin + R_WB (0, 0, height_m)); k_t = 6 x the pad's shear stiffness (y).
// - kOnStand: the object rests with its centre at stand_height_m. The pads touch it only while
//   they reach it (PadsReach: the frame within the object's half height plus the pads' half
//   height of its centre); beyond that the frame closes on nothing. When the pads start gripping
//   (normal force after none) the stick anchor is set to frame height - object height; the pads
//   then carry shear k_t ((frame height - object height) - anchor) + c_t (frame's vertical
//   speed), c_t = 6 x the pad's shear damping (y), capped at +-mu_s x grasp force
//   (at the cap the pads slide over the object and the anchor follows). The stand pushes up with
//   whatever of the weight the shear does not carry and never pulls; once the shear reaches m g
//   the object lifts (kHeld). The vehicle gets -shear along world z. The object's horizontal
//   inertia on the stand is neglected (the stand is taken as frictionless horizontally and the
//   object as light), so the normal forces stay symmetric.
// - kHeld: the object moves rigidly with the vehicle, whose step adds payload_mass_kg to its own
//   mass and weight and payload_inertia_kg_m2 to its inertia (force_on_vehicle_world_n = 0). The
//   pads must apply F = m x specific force (body): its z part is shear, shared by the pads in
//   proportion to their normal force; its horizontal part comes from a normal-force imbalance dN_i
//   = -o_i . (A^-1 F_h), A = sum o_i o_i^T = 3 I in the plane for six evenly spaced pads (the pads
//   on the side away from the push press harder). A pad that would have to pull loses contact
//   instead: the object shifts further toward the pads opposite, and the balance is solved again on
//   the pads still touching it (an active-set solve, only in such steps), so the pads always apply
//   F_h; GraspForces counts the released pads. Shear beyond mu_s x grasp force (or no grasp force)
//   starts kSliding; lowering the object until its centre would be below the stand puts it back on
//   the stand (kOnStand, with the shear carried over so nothing jumps).
// - kSliding: slip along body z, relative acceleration = friction / m - specific force z, friction
//   = -sign(slip rate) mu_k x grasp force, semi-implicit Euler (non-stiff: the friction is
//   bounded). From rest the object re-sticks (kHeld) if mu_s x grasp force can carry it, otherwise
//   it breaks away with kinetic friction. The pads still hold it horizontally (the imbalance above,
//   its reaction goes to the vehicle), the vehicle gets -(horizontal hold + friction) rotated to
//   world, payload 0. Slip beyond pad_half_height_m: kDropped (the object leaves the pads); its
//   centre reaching the stand: kOnStand.
// - kDropped, kDestroyed, kNoObject: no pad forces, no vehicle force, no servo load.
// Without the stand (stand_present false) an object still in kOnStand goes to kHeld at the next
// step (kDropped if the pads do not touch it), and the put-back rules are off.
// Damage: once the normal forces are known, any pad at DamageReached records the object's damage
// mode (once; it stays). kBurst and kShatter remove the object (kDestroyed from the next step; the
// step that broke it still reports its forces), kCrack and kCrush leave the mode as it is.
//
// Outputs. Pad i's film sees (tangential 0, y = -(shear share of pad i), z = +normal_i) in its
// sensor frame: the object pulls the films down when the pads hold it up. elastic_energy_j is the
// symmetric squeeze's energy in six pads and six object contacts plus the shear springs'
// shear^2 / (2 k_t); the imbalance's small extra energy is not included.
//
// NaN safety: non-finite vehicle inputs, angle, dt or state leave the mode unchanged and give zero
// forces; an invalid scene (ValidateGraspScene) starts as kNoObject and never produces forces.
// Per-step cost is a few series solves, each warm-started from the last, without heap allocation.
#ifndef HILRIG_HOST_PLANT_GRASP_CONTACT_H_
#define HILRIG_HOST_PLANT_GRASP_CONTACT_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "host/plant/gripper_frame.h"
#include "host/plant/object_model.h"
#include "host/plant/servo.h"
#include "rig/result.h"

namespace hilrig::host {

enum class GraspMode { kNoObject, kOnStand, kHeld, kSliding, kDropped, kDestroyed };
const char* GraspModeName(GraspMode mode);  // "no_object", "on_stand", "held", "sliding", ...

struct GraspSceneParams {
  ObjectParams object;
  GripperFrameParams frame;
  // One pad: (shear x, shear y, normal); the runner passes SiliconeStiffness(pad).
  Eigen::Vector3d pad_stiffness_n_per_m = {1.5e3, 1.5e3, 5.6e3};
  // One pad's Kelvin-Voigt damping (shear x, shear y, normal); the runner passes
  // SiliconeDamping(pad). It damps the stick spring that holds an object on its stand against the
  // vehicle's motion: without it that spring (6 x 1.5 N/mm against the vehicle) is an undamped
  // stiff mode sampled once per tick.
  Eigen::Vector3d pad_damping_n_s_per_m = Eigen::Vector3d::Zero();
  // Pad normal F = k d (1 + beta d^2); 0 = linear (the runner passes beta when stiffening is on).
  double pad_stiffening_per_m2 = 0.0;
  double stand_height_m = 0.5;  // world z of the object's centre while it rests on its stand
  // False once the stand (or the hand offering the object) is taken away: an object on it then
  // hangs on the pads (held, or sliding when friction cannot carry it; dropped when the pads do
  // not touch it), and nothing puts a held object back.
  bool stand_present = true;
  double pad_half_height_m = 0.010;  // after sliding this far the object leaves the pads
};

// The object (ValidateObject), the frame, positive finite pad stiffness, beta >= 0, finite stand
// height and positive pad half height; the message names the field.
rig::Result<void> ValidateGraspScene(const GraspSceneParams& params);

// The series solve behind SymmetricNormalForce, for one pad: the force at a given overlap, with
// the pad compression, the object indentation and the series stiffness dF/d(overlap).
struct SeriesContact {
  double force_n = 0;
  double pad_compression_m = 0;
  double indentation_m = 0;
  double stiffness_n_per_m = 0;
  double indentation_per_overlap = 0;  // the object's share of a small change of the overlap
};

// A solved series contact kept to warm-start a solve at a nearby overlap: the indentation there is
// predicted to first order, indentation_m + indentation_per_overlap * (overlap - overlap_m). Only
// the start of the iteration depends on it, never the tolerance. overlap_m <= 0: no seed.
struct SeriesSeed {
  double overlap_m = 0.0;
  double indentation_m = 0.0;
  double indentation_per_overlap = 0.0;  // d(indentation)/d(overlap) = k_pad / (k_object + k_pad)
  // The whole solve, when the seed came from SeedOf: a solve at exactly overlap_m (the servo's
  // search starts where the last grasp step solved) returns it instead of converging again to the
  // same answer. Only valid for the object and pad it was solved for, like the seed itself.
  bool has_solve = false;
  SeriesContact solve{};
};

struct GraspState {
  GraspMode mode = GraspMode::kOnStand;
  double object_mass_kg = 0.0;  // set from the params at start; grows with PourMass
  double object_height_m =
      0.0;  // world z of the object's centre (on stand; dropped: where it left)
  // Frame-above-object offset (m) at which the pads carry no shear: set when the pads grip on the
  // stand, kept while held or sliding as the reference the slip is measured from.
  double stand_anchor_m = 0.0;
  bool gripped = false;  // any normal force this step
  double slip_m = 0.0;   // object along body z relative to where it was held (down < 0)
  double slip_rate_m_s = 0.0;
  DamageMode damage = DamageMode::kNone;  // set once when the criterion is first reached
  double peak_normal_force_n = 0.0;
  double peak_indentation_m = 0.0;
  // The last contact solve, which warm-starts the next one (SeriesSeed): from one tick to the next
  // the overlap moves little, so its first-order prediction is usually already converged.
  SeriesSeed contact_seed;
  // What the pads pressed beyond six times the symmetric squeeze in the last step: zero while all
  // six touch (the imbalance sums to zero), positive once a push released some, since the object
  // then shifts onto the others. The servo holds it too (GraspServoLoad), one step late.
  double released_extra_normal_n = 0.0;
  // The object on its stand is out of the pads' reach (PadsReach): the frame closes on nothing.
  // The servo's load reads it, one step late like the released pads.
  bool out_of_reach = false;
};

// Whether pads whose ring plane is at world height `frame_height_m` reach an object whose centre
// is at `object_height_m`: |frame - object| < object.half_height_m + params.pad_half_height_m.
// False for non-finite heights.
bool PadsReach(const GraspSceneParams& params, double frame_height_m, double object_height_m);

// On the stand with the params' mass at the stand height; kNoObject when the scene does not
// validate (an invalid object is never put in the scene). Also how an object is replaced (the
// next fixture is put on the stand): start again from this state.
GraspState InitialGraspState(const GraspSceneParams& params);

struct GraspVehicleSample {  // the vehicle as it is at the start of this step
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();             // body origin, world
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // R_WB
  Eigen::Vector3d specific_force_body_m_s2 = {0, 0, 9.81};  // accelerometer on the body (last step)
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();   // body origin, world
  double gravity_m_s2 = 9.81;
};

// Six zero vectors: Eigen's default constructor leaves a vector uninitialized, so `{}` alone would
// not zero the pad forces.
inline std::array<Eigen::Vector3d, kGripperPadCount> ZeroPadVectors() {
  std::array<Eigen::Vector3d, kGripperPadCount> vectors;
  for (Eigen::Vector3d& v : vectors) v.setZero();
  return vectors;
}

struct GraspForces {
  // Force the object applies to each pad's film, in that pad's sensor frame (x tangential,
  // y body-up, z into the pad = compression).
  std::array<Eigen::Vector3d, kGripperPadCount> pad_force_n = ZeroPadVectors();
  std::array<double, kGripperPadCount> normal_force_n{};
  double grasp_force_n = 0;  // sum of normal forces (what the DUT's grasp force should read)
  // Sum of pad friction along body z carried for the object: + = pads hold the object up.
  double shear_force_n = 0;
  double indentation_m = 0;  // object indentation at each pad from the symmetric squeeze
  // Contact force on the vehicle NOT already represented by payload_mass_kg.
  Eigen::Vector3d force_on_vehicle_world_n = Eigen::Vector3d::Zero();
  // Object mass moving rigidly with the vehicle this step (held); the vehicle step adds it to its
  // own mass and weight.
  double payload_mass_kg = 0;
  // Its principal moments about the body origin, body axes (held): its own, inertia_factor m r^2,
  // plus m d^2 about x and y for its centre d along body z. The vehicle step adds them to its own.
  Eigen::Vector3d payload_inertia_kg_m2 = Eigen::Vector3d::Zero();
  double elastic_energy_j = 0;  // stored in the six pads and the object (for stability checks)
  // Pads that lost contact this step because holding the object horizontally would have made them
  // pull; the object shifted toward the pads opposite, which carry the hold alone.
  int released_pads = 0;
  // What the pads left of the horizontal hold unapplied (N): 0 whenever two pads not opposite each
  // other still touch the object, which any grip that holds it has.
  double unbalanced_horizontal_n = 0;
};

// Per-pad normal force at frame angle `angle_rad` from the symmetric squeeze (pad and object in
// series), 0 without overlap. Also returns the object's indentation. Zero when the object is
// absent, dropped or destroyed, and for a non-finite angle or an invalid scene.
double SymmetricNormalForce(const GraspSceneParams& params, const GraspState& state,
                            double angle_rad, double* indentation_m = nullptr);

// The series solve (SeriesContact above) from scratch.
SeriesContact SolveSeriesContact(const ObjectParams& object, double pad_normal_n_per_m,
                                 double pad_stiffening_per_m2, double overlap_m);
// The same, warm-started from a solve at a nearby overlap; an empty or non-finite seed, or a
// prediction outside (0, overlap), starts cold. A seed from SeedOf at exactly this overlap gives
// back the solve it keeps.
SeriesContact SolveSeriesContact(const ObjectParams& object, double pad_normal_n_per_m,
                                 double pad_stiffening_per_m2, double overlap_m,
                                 const SeriesSeed& seed);
// The seed a solve leaves for the next one at a nearby overlap (empty without overlap); it keeps
// the solve too.
SeriesSeed SeedOf(const SeriesContact& contact, double overlap_m);

// What the per-tick paths derive from the scene's params alone: computed once per scene (a caller
// stepping many ticks keeps it next to the params and recomputes it whenever it changes them)
// instead of once or several times per tick.
struct GraspSceneConstants {
  // ValidateGraspScene passes: the one check of the params, whose success path neither allocates
  // nor builds a message, so the steps and the servo load rely on the same ranges.
  bool scene_usable = false;
  // Outward direction of each pad (body x, y): pad 0's, the others following by 60 deg
  // rotations. The same for every tick of a scene, so the imbalance does not rotate it each time.
  // Zero until MakeGraspSceneConstants fills them (a default is not scene_usable either).
  std::array<double, kGripperPadCount> outward_x{};
  std::array<double, kGripperPadCount> outward_y{};
};
GraspSceneConstants MakeGraspSceneConstants(const GraspSceneParams& params);

// The grasp's load on the servo (closing_m_per_rad * sum of normal forces), as a ServoLoad. It
// keeps references to params and state: build it for the step, do not keep it beyond them.
class GraspServoLoad final : public ServoLoad {
 public:
  GraspServoLoad(const GraspSceneParams& params, const GraspState& state);
  // With the scene's constants already computed (they must be those of `params`).
  GraspServoLoad(const GraspSceneParams& params, const GraspSceneConstants& constants,
                 const GraspState& state);
  double TorqueAt(double angle_rad) const override;
  double TorqueAndSlopeAt(double angle_rad, double* slope_nm_per_rad) const override;

 private:
  const GraspSceneParams& params_;
  const GraspState& state_;
  // Whether there is an object to push against and a contact the series solve can take: fixed for
  // the load's short life, so the servo's search does not re-check it at every evaluation.
  bool loads_;
  // The servo's search evaluates a sequence of nearby angles, converging on one: each contact
  // solve seeds the next (starting from the state's seed), so most take a single Newton step. It
  // only changes where the iteration starts, never the answer's tolerance.
  mutable SeriesSeed seed_;
};

// One step: updates the mode, damage and sliding, and returns the forces of this step.
GraspForces StepGrasp(const GraspSceneParams& params, GraspState& state,
                      const GraspVehicleSample& vehicle, double frame_angle_rad, double dt_s);
// The same with the scene's constants already computed (they must be those of `params`).
GraspForces StepGrasp(const GraspSceneParams& params, const GraspSceneConstants& constants,
                      GraspState& state, const GraspVehicleSample& vehicle, double frame_angle_rad,
                      double dt_s);
// The same, writing this step's forces over `out`: a caller that keeps the forces from tick to
// tick saves copying them out of a returned value.
void StepGrasp(const GraspSceneParams& params, const GraspSceneConstants& constants,
               GraspState& state, const GraspVehicleSample& vehicle, double frame_angle_rad,
               double dt_s, GraspForces& out);

// Mass flow into a container (ignored when <= 0 or non-finite).
void PourMass(GraspState& state, double added_mass_kg);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_PLANT_GRASP_CONTACT_H_
