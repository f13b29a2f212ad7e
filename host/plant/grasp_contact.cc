#include "host/plant/grasp_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace hilrig::host {
namespace {

// The series solve stops once a Newton step moves the indentation by less than this fraction of
// the overlap; with quadratic convergence the step taken then leaves an error of order 1e-20.
constexpr double kSeriesTolerance = 1e-10;
constexpr int kSeriesNewtonTries = 30;
constexpr int kSeriesMaxIterations = 200;
// Held -> on stand needs the object's centre this far below the stand, so a frame hovering exactly
// at the lift threshold does not flip modes every tick.
constexpr double kStandHysteresisM = 1e-9;
// For six pads every 60 deg, A = sum_i o_i o_i^T = 3 I in the ring plane.
constexpr double kImbalanceGain = 2.0 / kGripperPadCount;

bool PositiveFinite(double value) { return std::isfinite(value) && value > 0; }

bool HasObject(GraspMode mode) {
  return mode == GraspMode::kOnStand || mode == GraspMode::kHeld || mode == GraspMode::kSliding;
}

double PadForce(double k, double beta, double d) { return k * d * (1.0 + beta * d * d); }
double PadStiffness(double k, double beta, double d) { return k * (1.0 + 3.0 * beta * d * d); }
double PadEnergy(double k, double beta, double d) {
  const double d2 = d * d;
  return k * d2 * (0.5 + 0.25 * beta * d2);
}

// Object indentation if the pad took none of the overlap's compliance, blended with the overlap
// itself: within a factor of two of the answer for power laws, which is all Newton needs.
double SeriesGuess(const ObjectParams& object, double pad_k, double overlap) {
  const double ratio = pad_k * overlap / object.stiffness;
  double object_only = 0.0;
  if (object.exponent == 1.0) {
    object_only = ratio;
  } else if (object.exponent == 1.5) {
    object_only = std::cbrt(ratio * ratio);
  } else {
    object_only = std::pow(ratio, 1.0 / object.exponent);
  }
  return object_only * overlap / (object_only + overlap);
}

bool InputsFinite(const GraspVehicleSample& v, double angle_rad, double dt_s) {
  return v.position_m.allFinite() && v.orientation.coeffs().allFinite() &&
         v.orientation.squaredNorm() > 0 && v.specific_force_body_m_s2.allFinite() &&
         v.velocity_m_s.allFinite() && std::isfinite(v.gravity_m_s2) && std::isfinite(angle_rad) &&
         std::isfinite(dt_s) && dt_s > 0;
}

bool StateFinite(const GraspState& s) {
  return std::isfinite(s.object_mass_kg) && s.object_mass_kg > 0 &&
         std::isfinite(s.object_height_m) && std::isfinite(s.stand_anchor_m) &&
         std::isfinite(s.slip_m) && std::isfinite(s.slip_rate_m_s) &&
         std::isfinite(s.peak_normal_force_n) && std::isfinite(s.peak_indentation_m);
}

// R_WB(2, 2) of a unit quaternion, written exactly as Eigen's toRotationMatrix computes it (so it
// rounds the same) without the other eight entries, which only sliding needs.
double BodyUpZ(const Eigen::Quaterniond& q) {
  const double tx = 2.0 * q.x();
  const double ty = 2.0 * q.y();
  return 1.0 - (tx * q.x() + ty * q.y());
}

// What every mode handler needs about this step.
struct StepContext {
  const GraspSceneParams& params;
  const GraspSceneConstants& constants;
  const GraspVehicleSample& vehicle;
  Eigen::Quaterniond world_from_body;  // normalized
  double frame_height_m;
  double body_up_z;  // world z of the body's up axis: converts body-z offsets into heights
  SeriesContact contact;
  double mass_kg;
  double shear_stiffness_n_per_m;  // k_t, all six pads together
  double dt_s;
};

// Fills the pad forces from per-pad normals and the shear the pads carry (shared by normal force).
void FillPadForces(const std::array<double, kGripperPadCount>& normals, double shear_n,
                   GraspForces& out) {
  double grasp = 0.0;
  for (double n : normals) grasp += n;
  out.normal_force_n = normals;
  out.grasp_force_n = grasp;
  out.shear_force_n = shear_n;
  for (int i = 0; i < kGripperPadCount; ++i) {
    const double share = grasp > 0 ? shear_n * normals[i] / grasp : 0.0;
    out.pad_force_n[i] = Eigen::Vector3d(0.0, -share, normals[i]);
  }
}

std::array<double, kGripperPadCount> SymmetricNormals(const StepContext& ctx) {
  std::array<double, kGripperPadCount> normals;
  normals.fill(ctx.contact.force_n);
  return normals;
}

// The pads' normals when they also push the object horizontally with `horizontal_body_n` (body x,
// y), F_h. Linearised about the symmetric squeeze N0, pad i carries N0 + o_i . u, where u is the
// object's horizontal shift toward the pads times their series stiffness; the pads push the object
// with -sum N_i o_i = F_h. With all six in contact u = -F_h / 3 (A = sum o_i o_i^T = 3 I): the pads
// on the side away from the push press harder, dN_i = -o_i . F_h / 3.
using PadNormals = std::array<double, kGripperPadCount>;

// Active-set iterations of ReleasePullingPads; each is one 2 x 2 solve.
constexpr int kReleaseIterations = 8;

// A pad that would have to pull (N0 + o_i . u < 0) loses contact instead: the object shifts
// further, and the pads still touching it carry the whole push. Solves the balance on the pads in
// contact, sum_{i in S} (N0 + o_i . u) o_i = -F_h, for u, and the contact set S again from u, until
// S holds: an active-set (semismooth Newton) search for the minimum of the convex contact energy
// sum max(0, N0 + o_i . u)^2 / 2 + F_h . u, which exists because the pads ring the object (some
// pad faces any push). Only a step in which a pad lets go comes here; a contact set that cannot
// carry the push (one pad, or two opposite ones) ends the search with the shortfall reported in
// `out`, with the released pads.
[[gnu::cold]] void ReleasePullingPads(const StepContext& ctx, double fx, double fy,
                                      PadNormals& normals, GraspForces& out) {
  const double n0 = ctx.contact.force_n;
  const auto& ox = ctx.constants.outward_x;
  const auto& oy = ctx.constants.outward_y;
  double ux = -kImbalanceGain * fx;
  double uy = -kImbalanceGain * fy;
  for (int iteration = 0; iteration < kReleaseIterations; ++iteration) {
    double a_xx = 0.0, a_xy = 0.0, a_yy = 0.0, b_x = -fx, b_y = -fy;
    for (int i = 0; i < kGripperPadCount; ++i) {
      if (!(n0 + ox[i] * ux + oy[i] * uy > 0)) continue;
      a_xx += ox[i] * ox[i];
      a_xy += ox[i] * oy[i];
      a_yy += oy[i] * oy[i];
      b_x -= n0 * ox[i];
      b_y -= n0 * oy[i];
    }
    // Unit vectors: a contact set of one pad, or of two opposite ones, leaves det at rounding.
    const double det = a_xx * a_yy - a_xy * a_xy;
    if (!(det > 1e-9)) break;
    const double next_ux = (a_yy * b_x - a_xy * b_y) / det;
    const double next_uy = (a_xx * b_y - a_xy * b_x) / det;
    bool same_set = true;
    for (int i = 0; i < kGripperPadCount; ++i) {
      same_set = same_set && ((n0 + ox[i] * ux + oy[i] * uy > 0) ==
                              (n0 + ox[i] * next_ux + oy[i] * next_uy > 0));
    }
    ux = next_ux;
    uy = next_uy;
    if (same_set) break;
  }
  double applied_x = 0.0;
  double applied_y = 0.0;
  out.released_pads = 0;
  for (int i = 0; i < kGripperPadCount; ++i) {
    normals[i] = std::max(0.0, n0 + ox[i] * ux + oy[i] * uy);
    out.released_pads += normals[i] > 0 ? 0 : 1;
    applied_x -= normals[i] * ox[i];
    applied_y -= normals[i] * oy[i];
  }
  out.unbalanced_horizontal_n = std::hypot(fx - applied_x, fy - applied_y);
}

PadNormals ImbalancedNormals(const StepContext& ctx, const Eigen::Vector3d& horizontal_body_n,
                             GraspForces& out) {
  PadNormals normals;
  const double vx = kImbalanceGain * horizontal_body_n.x();
  const double vy = kImbalanceGain * horizontal_body_n.y();
  const auto& ox = ctx.constants.outward_x;
  const auto& oy = ctx.constants.outward_y;
  bool pulls = false;
  for (int i = 0; i < kGripperPadCount; ++i) {
    const double normal = ctx.contact.force_n - (ox[i] * vx + oy[i] * vy);
    pulls = pulls || normal < 0;
    normals[i] = std::max(0.0, normal);
  }
  if (pulls) ReleasePullingPads(ctx, horizontal_body_n.x(), horizontal_body_n.y(), normals, out);
  return normals;
}

double Sum(const std::array<double, kGripperPadCount>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum;
}

// The normal force the pads press beyond the symmetric squeeze's six, nonzero only with released
// pads.
double ReleasedExtra(const StepContext& ctx, const PadNormals& normals, const GraspForces& out) {
  if (out.released_pads == 0) return 0.0;
  return std::max(0.0, Sum(normals) - kGripperPadCount * ctx.contact.force_n);
}

double ShearEnergy(const StepContext& ctx, double shear_n) {
  return shear_n * shear_n / (2.0 * ctx.shear_stiffness_n_per_m);
}

// Where the object's centre sits along body z, below the frame centre by the frame-above-object
// offset: the no-shear offset less the slip, plus the pads' shear deflection under `shear_n`.
double CarriedObjectOffset(const StepContext& ctx, const GraspState& s, double shear_n) {
  return s.stand_anchor_m - s.slip_m + shear_n / ctx.shear_stiffness_n_per_m;
}

// Height of the object's centre while the pads carry it with `shear_n`.
double CarriedObjectHeight(const StepContext& ctx, const GraspState& s, double shear_n) {
  return ctx.frame_height_m - ctx.body_up_z * CarriedObjectOffset(ctx, s, shear_n);
}

// The held object's principal moments about the body origin, in body axes: its own (a multiple of
// m r^2 about any axis through its centre) plus m d^2 about x and y for its centre d along body z.
Eigen::Vector3d HeldObjectInertia(const StepContext& ctx, const GraspState& s, double shear_n) {
  const ObjectParams& object = ctx.params.object;
  const double own =
      object.inertia_factor * ctx.mass_kg * object.half_width_m * object.half_width_m;
  const double centre_z_m = ctx.params.frame.height_m - CarriedObjectOffset(ctx, s, shear_n);
  const double offset = ctx.mass_kg * centre_z_m * centre_z_m;
  return Eigen::Vector3d(own + offset, own + offset, own);
}

void PutBackOnStand(const StepContext& ctx, GraspState& s) {
  // Fold the slip into the anchor so the stand's stick law starts with the shear the pads had.
  s.stand_anchor_m -= s.slip_m;
  s.slip_m = 0.0;
  s.slip_rate_m_s = 0.0;
  s.object_height_m = ctx.params.stand_height_m;
  s.mode = GraspMode::kOnStand;
}

void StepHeld(const StepContext& ctx, GraspState& s, GraspForces& out);

// The stand was taken away under the object: whatever grips it now carries it.
void LoseTheStand(const StepContext& ctx, GraspState& s, GraspForces& out) {
  if (!(ctx.contact.force_n > 0)) {
    s.mode = GraspMode::kDropped;
    out = GraspForces{};
    return;
  }
  if (!s.gripped) s.stand_anchor_m = ctx.frame_height_m - s.object_height_m;
  s.mode = GraspMode::kHeld;
  s.slip_m = 0.0;
  s.slip_rate_m_s = 0.0;
  StepHeld(ctx, s, out);
}

void StepOnStand(const StepContext& ctx, GraspState& s, GraspForces& out) {
  if (!ctx.params.stand_present) return LoseTheStand(ctx, s, out);
  const ObjectParams& object = ctx.params.object;
  s.object_height_m = ctx.params.stand_height_m;
  const double grasp = kGripperPadCount * ctx.contact.force_n;
  if (!(grasp > 0)) {
    FillPadForces(SymmetricNormals(ctx), 0.0, out);
    return;
  }
  const double offset = ctx.frame_height_m - s.object_height_m;
  if (!s.gripped) s.stand_anchor_m = offset;
  const double k_t = ctx.shear_stiffness_n_per_m;
  const double c_t = kGripperPadCount * ctx.params.pad_damping_n_s_per_m.y();
  const double frame_rise_m_s = ctx.vehicle.velocity_m_s.z();
  double shear = k_t * (offset - s.stand_anchor_m) + c_t * frame_rise_m_s;
  const double cap = object.friction_static * grasp;
  if (std::abs(shear) > cap) {
    shear = std::copysign(cap, shear);
    // The pads slide over the object to the cap.
    s.stand_anchor_m = offset - (shear - c_t * frame_rise_m_s) / k_t;
  }
  FillPadForces(SymmetricNormals(ctx), shear, out);
  out.force_on_vehicle_world_n = Eigen::Vector3d(0.0, 0.0, -shear);
  out.elastic_energy_j += ShearEnergy(ctx, shear);
  if (shear >= ctx.mass_kg * ctx.vehicle.gravity_m_s2) {
    s.mode = GraspMode::kHeld;
    s.slip_m = 0.0;
    s.slip_rate_m_s = 0.0;
  }
}

void StepHeld(const StepContext& ctx, GraspState& s, GraspForces& out) {
  const ObjectParams& object = ctx.params.object;
  const Eigen::Vector3d required_n = ctx.mass_kg * ctx.vehicle.specific_force_body_m_s2;
  const PadNormals normals = ImbalancedNormals(ctx, required_n, out);
  s.released_extra_normal_n = ReleasedExtra(ctx, normals, out);
  const double shear = required_n.z();
  FillPadForces(normals, shear, out);
  out.payload_mass_kg = ctx.mass_kg;
  out.payload_inertia_kg_m2 = HeldObjectInertia(ctx, s, shear);
  out.elastic_energy_j += ShearEnergy(ctx, shear);

  const double height = CarriedObjectHeight(ctx, s, shear);
  if (ctx.params.stand_present && height < ctx.params.stand_height_m - kStandHysteresisM) {
    PutBackOnStand(ctx, s);
    return;
  }
  s.object_height_m = height;
  const double grasp = out.grasp_force_n;
  if (!(grasp > 0) || std::abs(shear) > object.friction_static * grasp) {
    s.mode = GraspMode::kSliding;
    s.slip_rate_m_s = 0.0;
  }
}

void StepSliding(const StepContext& ctx, GraspState& s, GraspForces& out) {
  const ObjectParams& object = ctx.params.object;
  const Eigen::Vector3d& specific_force = ctx.vehicle.specific_force_body_m_s2;
  const Eigen::Vector3d horizontal_n(ctx.mass_kg * specific_force.x(),
                                     ctx.mass_kg * specific_force.y(), 0.0);
  const PadNormals normals = ImbalancedNormals(ctx, horizontal_n, out);
  s.released_extra_normal_n = ReleasedExtra(ctx, normals, out);
  const double grasp = Sum(normals);

  double friction = 0.0;
  const double rate = s.slip_rate_m_s;
  if (rate == 0.0) {
    const double needed = ctx.mass_kg * specific_force.z();
    if (grasp > 0 && std::abs(needed) <= object.friction_static * grasp) {
      s.mode = GraspMode::kHeld;  // re-sticks; the held step computes the forces
      return;
    }
    friction = std::copysign(object.friction_kinetic * grasp, needed);
  } else {
    friction = -std::copysign(object.friction_kinetic * grasp, rate);
  }
  const double relative_acceleration = friction / ctx.mass_kg - specific_force.z();
  const double next_rate = rate + relative_acceleration * ctx.dt_s;
  if (rate != 0.0 && next_rate * rate <= 0) {
    // Friction stops it within the step: it covers the distance of a uniform deceleration and
    // rests, so the next step decides whether it sticks.
    s.slip_m += 0.5 * rate * (-rate / relative_acceleration);
    s.slip_rate_m_s = 0.0;
  } else {
    s.slip_rate_m_s = next_rate;
    s.slip_m += next_rate * ctx.dt_s;  // semi-implicit Euler
  }

  const double height = CarriedObjectHeight(ctx, s, friction);
  if (std::abs(s.slip_m) > ctx.params.pad_half_height_m) {
    s.mode = GraspMode::kDropped;
    s.object_height_m = height;
    s.slip_rate_m_s = 0.0;
    out = GraspForces{};
    return;
  }
  FillPadForces(normals, friction, out);
  // The same matrix product as always (not a quaternion rotation), so the force rounds the same.
  out.force_on_vehicle_world_n = -(ctx.world_from_body.toRotationMatrix() *
                                   (horizontal_n + Eigen::Vector3d(0.0, 0.0, friction)));
  out.elastic_energy_j += ShearEnergy(ctx, friction);
  if (ctx.params.stand_present && height <= ctx.params.stand_height_m) {
    PutBackOnStand(ctx, s);
    return;
  }
  s.object_height_m = height;
}

// `largest_normal_n` is the largest finite normal force of the step (-inf if none): every pad
// shares the indentation, so that pad reaches the criterion first if any does.
void RecordDamage(const ObjectParams& object, double largest_normal_n, double indentation_m,
                  GraspState& s) {
  if (s.damage != DamageMode::kNone || object.damage_mode == DamageMode::kNone) return;
  if (!DamageReached(object, largest_normal_n, indentation_m)) return;
  s.damage = object.damage_mode;
  if (s.damage == DamageMode::kBurst || s.damage == DamageMode::kShatter) {
    s.mode = GraspMode::kDestroyed;
  }
}

}  // namespace

const char* GraspModeName(GraspMode mode) {
  switch (mode) {
    case GraspMode::kNoObject:
      return "no_object";
    case GraspMode::kOnStand:
      return "on_stand";
    case GraspMode::kHeld:
      return "held";
    case GraspMode::kSliding:
      return "sliding";
    case GraspMode::kDropped:
      return "dropped";
    case GraspMode::kDestroyed:
      return "destroyed";
  }
  return "unknown";
}

rig::Result<void> ValidateGraspScene(const GraspSceneParams& p) {
  if (auto object = ValidateObject(p.object); !object.ok()) return object;
  if (auto frame = ValidateGripperFrame(p.frame); !frame.ok()) return frame;
  if (!p.pad_stiffness_n_per_m.allFinite() || !(p.pad_stiffness_n_per_m.minCoeff() > 0)) {
    return rig::MakeError("grasp scene: pad_stiffness_n_per_m: every axis must be finite and > 0");
  }
  if (!std::isfinite(p.pad_stiffening_per_m2) || p.pad_stiffening_per_m2 < 0) {
    return rig::MakeError("grasp scene: pad_stiffening_per_m2: must be finite and >= 0");
  }
  if (!std::isfinite(p.stand_height_m)) {
    return rig::MakeError("grasp scene: stand_height_m: must be finite");
  }
  if (!PositiveFinite(p.pad_half_height_m)) {
    return rig::MakeError("grasp scene: pad_half_height_m: must be finite and > 0");
  }
  return {};
}

GraspState InitialGraspState(const GraspSceneParams& params) {
  GraspState state;
  state.mode = ValidateGraspScene(params).ok() ? GraspMode::kOnStand : GraspMode::kNoObject;
  state.object_mass_kg = std::isfinite(params.object.mass_kg) ? params.object.mass_kg : 0.0;
  state.object_height_m = std::isfinite(params.stand_height_m) ? params.stand_height_m : 0.0;
  return state;
}

namespace {

// The series solve from an initial indentation guess (used when inside (0, overlap)).
SeriesContact SolveSeriesFrom(const ObjectParams& object, double pad_k, double pad_beta,
                              double overlap, double guess_m) {
  SeriesContact c;
  if (!(overlap > 0) || !std::isfinite(overlap)) return c;
  const bool object_linear = object.exponent == 1.0 && std::isinf(object.stiffening_length_m);
  if (object_linear && pad_beta == 0.0) {
    const double k = object.stiffness;
    const double sum = k + pad_k;
    c.indentation_m = overlap * (pad_k / sum);
    c.pad_compression_m = overlap * (k / sum);
    c.stiffness_n_per_m = k * (pad_k / sum);
    c.indentation_per_overlap = pad_k / sum;
    c.force_n = overlap * c.stiffness_n_per_m;
    return c;
  }

  // Force balance h(d) = F_object(d) - F_pad(overlap - d), increasing in d on [0, overlap].
  double lo = 0.0;
  double hi = overlap;
  double d = guess_m > lo && guess_m < hi ? guess_m : SeriesGuess(object, pad_k, overlap);
  if (!(d > lo && d < hi)) d = 0.5 * overlap;
  double object_force = 0.0;
  double object_k = 0.0;
  double pad_force = 0.0;
  double pad_k_now = pad_k;
  double step = 0.0;  // the last, accepted Newton step (applied to the values below by linearity)
  for (int iteration = 0; iteration < kSeriesMaxIterations; ++iteration) {
    const double pad_d = overlap - d;
    object_force = ObjectContactForceAndStiffness(object, d, &object_k);
    pad_force = PadForce(pad_k, pad_beta, pad_d);
    pad_k_now = PadStiffness(pad_k, pad_beta, pad_d);
    const double residual = object_force - pad_force;
    step = 0.0;
    if (residual > 0) {
      hi = d;
    } else if (residual < 0) {
      lo = d;
    } else {
      break;
    }
    // Newton is quadratic here: once its step is this small, taking it leaves an error far below
    // rounding, and the forces follow it to first order without another evaluation.
    const double newton = -residual / (object_k + pad_k_now);
    if (std::abs(newton) <= kSeriesTolerance * overlap) {
      step = newton;
      break;
    }
    if (hi - lo <= kSeriesTolerance * overlap) break;
    const double next = d + newton;
    const bool newton_ok = iteration < kSeriesNewtonTries && next > lo && next < hi;
    d = newton_ok ? next : 0.5 * (lo + hi);
  }

  c.indentation_m = std::clamp(d + step, 0.0, overlap);
  c.pad_compression_m = overlap - c.indentation_m;
  // Read the force off the softer side: its displacement is the large, well-resolved one, so the
  // force keeps full relative precision even when the other side is 1e9 times stiffer.
  c.force_n = object_k <= pad_k_now ? object_force + object_k * step : pad_force - pad_k_now * step;
  const double k_sum = object_k + pad_k_now;
  c.stiffness_n_per_m = k_sum > 0 ? object_k * pad_k_now / k_sum : 0.0;
  c.indentation_per_overlap = k_sum > 0 ? pad_k_now / k_sum : 0.0;
  return c;
}

}  // namespace

SeriesContact SolveSeriesContact(const ObjectParams& object, double pad_k, double pad_beta,
                                 double overlap) {
  return SolveSeriesFrom(object, pad_k, pad_beta, overlap, -1.0);
}

SeriesContact SolveSeriesContact(const ObjectParams& object, double pad_k, double pad_beta,
                                 double overlap, const SeriesSeed& seed) {
  // The same input as the solve the seed keeps: its answer, to the solve's own tolerance.
  if (seed.has_solve && overlap == seed.overlap_m) return seed.solve;
  // A NaN prediction fails the range check in the solve and starts cold.
  const double guess = seed.overlap_m > 0 ? seed.indentation_m + seed.indentation_per_overlap *
                                                                     (overlap - seed.overlap_m)
                                          : -1.0;
  return SolveSeriesFrom(object, pad_k, pad_beta, overlap, guess);
}

SeriesSeed SeedOf(const SeriesContact& contact, double overlap_m) {
  if (!(overlap_m > 0) || !std::isfinite(contact.indentation_m)) return {};
  return {overlap_m, contact.indentation_m, contact.indentation_per_overlap, true, contact};
}

GraspSceneConstants MakeGraspSceneConstants(const GraspSceneParams& params) {
  GraspSceneConstants constants;
  constants.scene_usable = ValidateGraspScene(params).ok();
  double ox = 1.0;
  double oy = 0.0;
  if (std::isfinite(params.frame.first_azimuth_rad)) {
    ox = std::cos(params.frame.first_azimuth_rad);
    oy = std::sin(params.frame.first_azimuth_rad);
  }
  // The first outward vector rotated by 60 deg per pad, not six sin/cos: two products a pad, and
  // the pads' directions (and so the residual imbalance of their forces) rounded one way for
  // every scene.
  const double c60 = 0.5;
  const double s60 = std::sqrt(3.0) / 2.0;
  for (int i = 0; i < kGripperPadCount; ++i) {
    constants.outward_x[i] = ox;
    constants.outward_y[i] = oy;
    const double next_x = c60 * ox - s60 * oy;
    oy = s60 * ox + c60 * oy;
    ox = next_x;
  }
  return constants;
}

double SymmetricNormalForce(const GraspSceneParams& params, const GraspState& state,
                            double angle_rad, double* indentation_m) {
  if (indentation_m != nullptr) *indentation_m = 0.0;
  if (!HasObject(state.mode) || !std::isfinite(angle_rad) || !ValidateGraspScene(params).ok()) {
    return 0.0;
  }
  const double overlap = params.object.half_width_m - PadSurfaceRadius(params.frame, angle_rad);
  const SeriesContact c =
      SolveSeriesContact(params.object, params.pad_stiffness_n_per_m.z(),
                         params.pad_stiffening_per_m2, overlap, state.contact_seed);
  if (!std::isfinite(c.force_n) || !(c.force_n >= 0)) return 0.0;
  if (indentation_m != nullptr) *indentation_m = c.indentation_m;
  return c.force_n;
}

GraspServoLoad::GraspServoLoad(const GraspSceneParams& params, const GraspState& state)
    : GraspServoLoad(params, MakeGraspSceneConstants(params), state) {}

GraspServoLoad::GraspServoLoad(const GraspSceneParams& params, const GraspSceneConstants& constants,
                               const GraspState& state)
    : params_(params),
      state_(state),
      loads_(HasObject(state.mode) && constants.scene_usable && !state.out_of_reach),
      seed_(state.contact_seed) {}

double GraspServoLoad::TorqueAt(double angle_rad) const {
  double slope_nm_per_rad = 0.0;
  return TorqueAndSlopeAt(angle_rad, &slope_nm_per_rad);
}

double GraspServoLoad::TorqueAndSlopeAt(double angle_rad, double* slope_nm_per_rad) const {
  *slope_nm_per_rad = 0.0;
  if (!loads_ || !std::isfinite(angle_rad)) return 0.0;
  const double closing = params_.frame.closing_m_per_rad;
  const double radius = PadSurfaceRadius(params_.frame, angle_rad);
  const double overlap = params_.object.half_width_m - radius;
  const SeriesContact c = SolveSeriesContact(params_.object, params_.pad_stiffness_n_per_m.z(),
                                             params_.pad_stiffening_per_m2, overlap, seed_);
  if (overlap > 0) seed_ = SeedOf(c, overlap);
  // Pads a push released leave the others pressing harder, and the frame holds their sum.
  const double extra_n = overlap > 0 ? state_.released_extra_normal_n : 0.0;
  const double torque = closing * (kGripperPadCount * c.force_n + extra_n);
  if (!(torque >= 0) || !std::isfinite(torque) || !std::isfinite(c.stiffness_n_per_m)) return 0.0;
  // d(overlap)/d(angle) = closing while the pads have not reached the centre.
  *slope_nm_per_rad = radius > 0 ? closing * closing * kGripperPadCount * c.stiffness_n_per_m : 0.0;
  return torque;
}

GraspForces StepGrasp(const GraspSceneParams& params, GraspState& state,
                      const GraspVehicleSample& vehicle, double frame_angle_rad, double dt_s) {
  return StepGrasp(params, MakeGraspSceneConstants(params), state, vehicle, frame_angle_rad, dt_s);
}

GraspForces StepGrasp(const GraspSceneParams& params, const GraspSceneConstants& constants,
                      GraspState& state, const GraspVehicleSample& vehicle, double frame_angle_rad,
                      double dt_s) {
  GraspForces out;
  StepGrasp(params, constants, state, vehicle, frame_angle_rad, dt_s, out);
  return out;
}

void StepGrasp(const GraspSceneParams& params, const GraspSceneConstants& constants,
               GraspState& state, const GraspVehicleSample& vehicle, double frame_angle_rad,
               double dt_s, GraspForces& out) {
  out = GraspForces{};
  if (!HasObject(state.mode)) {
    state.gripped = false;
    return;
  }
  if (!InputsFinite(vehicle, frame_angle_rad, dt_s) || !StateFinite(state) ||
      !constants.scene_usable) {
    return;
  }
  const Eigen::Quaterniond world_from_body = vehicle.orientation.normalized();
  const double body_up_z = BodyUpZ(world_from_body);
  const double frame_height_m = vehicle.position_m.z() + body_up_z * params.frame.height_m;
  // Only an object on its stand can be out of reach: a held or sliding one moves with the pads.
  state.out_of_reach = state.mode == GraspMode::kOnStand &&
                       !PadsReach(params, frame_height_m, state.object_height_m);
  const double overlap = state.out_of_reach ? 0.0
                                            : params.object.half_width_m -
                                                  PadSurfaceRadius(params.frame, frame_angle_rad);
  StepContext ctx{params,
                  constants,
                  vehicle,
                  world_from_body,
                  frame_height_m,
                  body_up_z,
                  SolveSeriesContact(params.object, params.pad_stiffness_n_per_m.z(),
                                     params.pad_stiffening_per_m2, overlap, state.contact_seed),
                  state.object_mass_kg,
                  kGripperPadCount * params.pad_stiffness_n_per_m.y(),
                  dt_s};
  if (!std::isfinite(ctx.contact.force_n)) return;
  if (overlap > 0) state.contact_seed = SeedOf(ctx.contact, overlap);

  // A transition re-runs the new mode's handler in the same step; a mode already visited this
  // step is not run again, so the step always ends (the last handler's forces stand).
  unsigned visited = 0;
  for (;;) {
    const GraspMode mode = state.mode;
    if (visited != 0) out = GraspForces{};  // a re-run starts from clean forces
    state.released_extra_normal_n = 0.0;    // the held and sliding steps set it
    visited |= 1u << static_cast<unsigned>(mode);
    switch (mode) {
      case GraspMode::kOnStand:
        StepOnStand(ctx, state, out);
        break;
      case GraspMode::kHeld:
        StepHeld(ctx, state, out);
        break;
      case GraspMode::kSliding:
        StepSliding(ctx, state, out);
        break;
      default:
        break;
    }
    if (state.mode == mode || !HasObject(state.mode) ||
        (visited & (1u << static_cast<unsigned>(state.mode))) != 0) {
      break;
    }
  }
  if (!HasObject(state.mode)) {  // dropped this step: nothing touches the pads any more
    state.gripped = false;
    state.released_extra_normal_n = 0.0;
    out = GraspForces{};
    return;
  }

  out.indentation_m = ctx.contact.indentation_m;
  out.elastic_energy_j +=
      kGripperPadCount * (PadEnergy(params.pad_stiffness_n_per_m.z(), params.pad_stiffening_per_m2,
                                    ctx.contact.pad_compression_m) +
                          ObjectContactEnergy(params.object, ctx.contact.indentation_m));
  state.gripped = out.grasp_force_n > 0;
  double largest_finite_normal_n = -std::numeric_limits<double>::infinity();
  for (double normal : out.normal_force_n) {
    state.peak_normal_force_n = std::max(state.peak_normal_force_n, normal);
    if (std::isfinite(normal)) largest_finite_normal_n = std::max(largest_finite_normal_n, normal);
  }
  state.peak_indentation_m = std::max(state.peak_indentation_m, out.indentation_m);
  RecordDamage(params.object, largest_finite_normal_n, out.indentation_m, state);
}

bool PadsReach(const GraspSceneParams& params, double frame_height_m, double object_height_m) {
  return std::abs(frame_height_m - object_height_m) <
         params.object.half_height_m + params.pad_half_height_m;
}

void PourMass(GraspState& state, double added_mass_kg) {
  if (!std::isfinite(added_mass_kg) || added_mass_kg <= 0) return;
  state.object_mass_kg += added_mass_kg;
}

}  // namespace hilrig::host
