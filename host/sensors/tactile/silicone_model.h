// Mechanics of one tactile pad: the 20 x 20 x 7 mm Ecoflex 00-30 block between the Hall chip's
// board and the magnetized film. A force on the film deforms the block; the film's displacement
// is what the magnetics see. The block is a linear spring per axis whose stiffness follows from
// the material (E, G) and the block's shape, with optional cubic stiffening of the normal axis
// (the block hardens as it is squeezed flat) and optional Kelvin-Voigt damping (a dashpot in
// parallel, c = retardation time x k) with an optional film mass. All of it is physics in the
// forward direction: force in, displacement out.
//
// Frames and signs. The pad frame is the chip (sensor) frame of film_field.h: the film rests at
// (0, 0, -10 mm), below the chip, so chip +z points from the film through the block to the chip.
// force_pad_n is the force that the contact applies to the film, in those axes: +z presses the
// film towards the chip (compression), x and y are shear. The displacement is the film's, in the
// same axes, so compression gives displacement.z() > 0 and the film centre moves to
// rest.z + displacement.z (closer to the chip). Shear translates the film without tilting it, as
// for a block bonded on both faces.
//
// Stiffness from material (defaults: E = 80 kPa, G = E / 3 for an incompressible rubber):
//   shear   k_s = G A / h                                    (simple shear of the block)
//   normal  k_n = E_c A / h,  E_c = E (1 + 2 k_gl S^2),  S = a b / (2 (a + b) h)
// E_c is the apparent compression modulus of a bonded block (Gent & Lindley 1959): the bonded
// faces stop the incompressible rubber from bulging, which stiffens it by the shape factor S
// (loaded area over free area; 0.714 for this block). k_gl is Gent's hardness-dependent factor;
// 0.4 is used because the top face carries a thin flexible film rather than a rigid plate, so the
// lateral constraint is partial. Then k_n = 1.408 E A / h and, for E = 50..120 kPa,
// k_n = 4.0..9.7 N/mm and k_s = 0.95..2.3 N/mm, i.e. the design's 4-10 and ~1-2.3 N/mm bands.
// Explicit stiffness overrides replace the material-derived values (e.g. from a jig fit).
//
// Time stepping. The state is integrated with the force held over the step. The massless
// linear case uses the exact exponential solution; everything else (a film mass, stiffening)
// uses backward Euler, which is L-stable: stiff parameters at dt = 1 ms decay instead of blowing
// up or ringing, at the cost of extra numerical damping of modes far above the 50 Hz sample rate.
#ifndef HILRIG_HOST_SENSORS_TACTILE_SILICONE_MODEL_H_
#define HILRIG_HOST_SENSORS_TACTILE_SILICONE_MODEL_H_

#include <Eigen/Core>
#include <optional>

#include "host/sensors/tactile/film_field.h"

namespace hilrig::host {

struct SiliconeParams {
  // Material: Ecoflex 00-30, E ~ 50-120 kPa depending on cure and strain rate.
  double youngs_modulus_pa = 80e3;
  // Unset: E / 3 (incompressible rubber, Poisson ratio 0.5).
  std::optional<double> shear_modulus_pa;
  // Block geometry.
  double width_x_m = 0.020;
  double width_y_m = 0.020;
  double thickness_m = 0.007;
  // Gent-Lindley factor of the bonded-block compression correction (see the header comment).
  double bulge_factor = 0.4;
  // Explicit stiffness overrides; when set they replace the material-derived values.
  std::optional<double> normal_stiffness_override_n_per_m;
  std::optional<double> shear_stiffness_override_n_per_m;

  // Normal stiffening: F_z = k_n delta (1 + beta delta^2), delta the normal displacement. The
  // default beta doubles the secant stiffness at half the block thickness (3.5 mm).
  bool stiffening_enabled = false;
  double stiffening_per_m2 = 1.0 / (0.0035 * 0.0035);

  // Kelvin-Voigt damping, c_axis = retardation_time_s * k_axis (the retardation time is a
  // material constant eta / E, so one number serves all axes). Off: the block is quasi-static
  // and follows the force instantly.
  bool damping_enabled = true;
  double retardation_time_s = 0.005;
  // Mass moved with the film (film plus a share of the silicone). Zero: first-order
  // Kelvin-Voigt; positive: a second-order mass-spring-damper per axis.
  double moving_mass_kg = 0.0;

  // Film pose at zero displacement.
  FilmPose rest_pose;
};

struct SiliconeState {
  Eigen::Vector3d displacement_m = Eigen::Vector3d::Zero();  // film, pad frame
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();    // used only with a moving mass
};

// Small-displacement stiffness per pad axis (x, y shear; z normal), N/m, after overrides.
Eigen::Vector3d SiliconeStiffness(const SiliconeParams& params);
// Kelvin-Voigt damping per axis, N s/m (zero when damping is disabled).
Eigen::Vector3d SiliconeDamping(const SiliconeParams& params);

// Displacement at which the block's elastic force balances force_pad_n.
Eigen::Vector3d StaticDisplacement(const SiliconeParams& params,
                                   const Eigen::Vector3d& force_pad_n);

// What a step of length dt_s derives from the parameters alone, per pad axis: a node stepping at
// a fixed rate builds it once instead of recomputing stiffness, damping and the relaxation factor
// exp(-k dt / c) on every sample.
struct SiliconeStep {
  double dt_s = 0.0;
  Eigen::Vector3d stiffness_n_per_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d damping_n_s_per_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d stiffening_per_m2 = Eigen::Vector3d::Zero();  // beta, nonzero only on z
  double moving_mass_kg = 0.0;  // zero unless damping is on (see StepSilicone)
  // exp(-k dt / c) where the axis is massless, linear and damped (the exact relaxation); else 0.
  Eigen::Vector3d relaxation_decay = Eigen::Vector3d::Zero();
};

// Aborts on a negative (or NaN) dt_s or moving mass and on parameters SiliconeStiffness rejects.
SiliconeStep MakeSiliconeStep(const SiliconeParams& params, double dt_s);

// Advances the block by step.dt_s with force_pad_n held over the step.
SiliconeState StepSilicone(const SiliconeStep& step, const SiliconeState& state,
                           const Eigen::Vector3d& force_pad_n);

// The same for a one-off step: MakeSiliconeStep, then the step.
SiliconeState StepSilicone(const SiliconeParams& params, const SiliconeState& state,
                           const Eigen::Vector3d& force_pad_n, double dt_s);

// Film pose in the chip frame for the current displacement.
FilmPose FilmPoseFor(const SiliconeParams& params, const SiliconeState& state);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_SENSORS_TACTILE_SILICONE_MODEL_H_
