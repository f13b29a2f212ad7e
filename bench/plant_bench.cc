// The vehicle's rigid-body step per physics tick with each fixed-step integrator, in hovering
// flight with a small torque so the attitude actually turns: the plant's share of the lockstep
// tick that does not depend on the grasp.
#include <benchmark/benchmark.h>

#include "host/plant/rigid_body.h"

namespace hilrig::host {
namespace {

void RigidBodyStep(benchmark::State& state, Integrator integrator) {
  const RigidBodyParams params;
  RigidBodyState body;
  body.position_m = {0.0, 0.0, 1.0};
  body.angular_velocity_rad_s = {0.02, -0.01, 0.05};
  Wrench wrench;
  wrench.force_world_n = {0.01, 0.0, params.mass_kg * 9.81};
  wrench.torque_body_nm = {1e-5, -2e-5, 1e-5};
  for (auto _ : state) {
    body = StepRigidBody(params, body, wrench, 9.81, 1e-3, integrator);
    benchmark::DoNotOptimize(body);
  }
}

void BM_RigidBodyStepRk4(benchmark::State& state) { RigidBodyStep(state, Integrator::kRk4); }
BENCHMARK(BM_RigidBodyStepRk4);
void BM_RigidBodyStepMidpoint(benchmark::State& state) {
  RigidBodyStep(state, Integrator::kMidpoint);
}
BENCHMARK(BM_RigidBodyStepMidpoint);

}  // namespace
}  // namespace hilrig::host
