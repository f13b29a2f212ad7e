#include "host/sensors/tactile/silicone_model.h"

#include <cmath>

#include "rig/check.h"

namespace hilrig::host {
namespace {

constexpr int kNormalAxis = 2;

double StiffeningOf(const SiliconeParams& params, int axis) {
  return (params.stiffening_enabled && axis == kNormalAxis) ? params.stiffening_per_m2 : 0.0;
}

// Solves a x + k x (1 + beta x^2) = b for x. Every implicit step and the static balance reduce to
// this with a >= 0, k > 0, beta >= 0, so the left side is strictly increasing and the root
// unique. Newton starts at the linear solution, which lies on the far side of the root (the
// cubic term only adds restoring force) where the function is convex towards the root, so the
// iterates approach it monotonically and never overshoot into a wrong branch.
double SolveAxis(double a, double k, double beta, double b) {
  const double linear = b / (a + k);
  if (beta == 0.0) return linear;
  double x = linear;
  for (int i = 0; i < 100; ++i) {
    const double g = (a + k) * x + k * beta * x * x * x - b;
    const double dg = a + k + 3.0 * k * beta * x * x;
    const double step = g / dg;
    x -= step;
    if (std::abs(step) <= 1e-15 + 1e-13 * std::abs(x)) break;
  }
  return x;
}

}  // namespace

Eigen::Vector3d SiliconeStiffness(const SiliconeParams& params) {
  HILRIG_CHECK(params.youngs_modulus_pa > 0.0 && params.thickness_m > 0.0 &&
                   params.width_x_m > 0.0 && params.width_y_m > 0.0,
               "silicone block needs positive modulus and dimensions");
  const double area_m2 = params.width_x_m * params.width_y_m;
  const double shear_modulus_pa = params.shear_modulus_pa.value_or(params.youngs_modulus_pa / 3.0);
  const double shape_factor =
      area_m2 / (2.0 * (params.width_x_m + params.width_y_m) * params.thickness_m);
  const double compression_modulus_pa =
      params.youngs_modulus_pa * (1.0 + 2.0 * params.bulge_factor * shape_factor * shape_factor);

  const double shear = params.shear_stiffness_override_n_per_m.value_or(shear_modulus_pa * area_m2 /
                                                                        params.thickness_m);
  const double normal = params.normal_stiffness_override_n_per_m.value_or(
      compression_modulus_pa * area_m2 / params.thickness_m);
  HILRIG_CHECK(shear > 0.0 && normal > 0.0, "silicone stiffness must be positive");
  return {shear, shear, normal};
}

Eigen::Vector3d SiliconeDamping(const SiliconeParams& params) {
  if (!params.damping_enabled) return Eigen::Vector3d::Zero();
  HILRIG_CHECK(params.retardation_time_s >= 0.0, "retardation time must not be negative");
  return params.retardation_time_s * SiliconeStiffness(params);
}

Eigen::Vector3d StaticDisplacement(const SiliconeParams& params,
                                   const Eigen::Vector3d& force_pad_n) {
  const Eigen::Vector3d k = SiliconeStiffness(params);
  Eigen::Vector3d x;
  for (int i = 0; i < 3; ++i) x[i] = SolveAxis(0.0, k[i], StiffeningOf(params, i), force_pad_n[i]);
  return x;
}

SiliconeStep MakeSiliconeStep(const SiliconeParams& params, double dt_s) {
  HILRIG_CHECK(dt_s >= 0.0, "silicone step needs dt >= 0");
  HILRIG_CHECK(params.moving_mass_kg >= 0.0, "moving mass must not be negative");
  SiliconeStep step;
  step.dt_s = dt_s;
  step.stiffness_n_per_m = SiliconeStiffness(params);
  step.damping_n_s_per_m = SiliconeDamping(params);
  // The mass only matters together with damping: without a dashpot the undamped oscillator
  // would ring forever, which no silicone does, so "damping off" means quasi-static.
  step.moving_mass_kg = params.damping_enabled ? params.moving_mass_kg : 0.0;
  for (int i = 0; i < 3; ++i) {
    const double k = step.stiffness_n_per_m[i];
    const double c = step.damping_n_s_per_m[i];
    step.stiffening_per_m2[i] = StiffeningOf(params, i);
    if (c != 0.0 && step.moving_mass_kg == 0.0 && step.stiffening_per_m2[i] == 0.0) {
      step.relaxation_decay[i] = std::exp(-k * dt_s / c);
    }
  }
  return step;
}

SiliconeState StepSilicone(const SiliconeStep& step, const SiliconeState& state,
                           const Eigen::Vector3d& force_pad_n) {
  const double dt_s = step.dt_s;
  const Eigen::Vector3d& k = step.stiffness_n_per_m;
  const Eigen::Vector3d& c = step.damping_n_s_per_m;
  const double m = step.moving_mass_kg;
  if (dt_s == 0.0) return state;
  SiliconeState next;
  for (int i = 0; i < 3; ++i) {
    const double beta = step.stiffening_per_m2[i];
    const double x0 = state.displacement_m[i];
    const double v0 = (m > 0.0) ? state.velocity_m_s[i] : 0.0;
    if (c[i] == 0.0 && m == 0.0) {
      next.displacement_m[i] = SolveAxis(0.0, k[i], beta, force_pad_n[i]);
      next.velocity_m_s[i] = 0.0;
      continue;
    }
    if (m == 0.0 && beta == 0.0) {
      // Exact solution of c x' + k x = F with F constant: first-order relaxation.
      const double x_ss = force_pad_n[i] / k[i];
      next.displacement_m[i] = x_ss + (x0 - x_ss) * step.relaxation_decay[i];
      next.velocity_m_s[i] = 0.0;
      continue;
    }
    // Backward Euler on m x'' + c x' + f_k(x) = F with v1 = (x1 - x0) / dt:
    //   (m / dt^2 + c / dt) x1 + f_k(x1) = F + m (x0 + dt v0) / dt^2 + c x0 / dt.
    const double a = m / (dt_s * dt_s) + c[i] / dt_s;
    const double b = force_pad_n[i] + m * (x0 + dt_s * v0) / (dt_s * dt_s) + c[i] * x0 / dt_s;
    const double x1 = SolveAxis(a, k[i], beta, b);
    next.displacement_m[i] = x1;
    next.velocity_m_s[i] = (m > 0.0) ? (x1 - x0) / dt_s : 0.0;
  }
  return next;
}

SiliconeState StepSilicone(const SiliconeParams& params, const SiliconeState& state,
                           const Eigen::Vector3d& force_pad_n, double dt_s) {
  return StepSilicone(MakeSiliconeStep(params, dt_s), state, force_pad_n);
}

FilmPose FilmPoseFor(const SiliconeParams& params, const SiliconeState& state) {
  FilmPose pose = params.rest_pose;
  pose.centre_m += state.displacement_m;
  return pose;
}

}  // namespace hilrig::host
