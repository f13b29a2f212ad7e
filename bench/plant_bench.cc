// The vehicle's rigid-body step per physics tick with each fixed-step integrator, in hovering
// flight with a small torque so the attitude actually turns: the plant's share of the lockstep
// tick that does not depend on the grasp; and the whole vehicle step around it.
#include <benchmark/benchmark.h>

#include "host/plant/quadrotor.h"
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

// The whole vehicle step as the runner takes it each tick: rotors, drag, wrench and the RK4 body,
// hovering with slightly uneven thrusts so the attitude turns.
void BM_QuadrotorStepHover(benchmark::State& state) {
  const QuadrotorParams params;
  const QuadrotorStepSize step = MakeQuadrotorStepSize(params, 1e-3);
  QuadrotorState vehicle = MakeHoveringQuadrotor(params, {0.0, 0.0, 1.0}, 0.0);
  const double hover = HoverThrustPerRotor(params);
  const std::array<double, kRotorCount> thrust_n = {hover + 1e-4, hover - 1e-4, hover, hover};
  const Eigen::Vector3d external_n(0.01, 0.0, 0.0);
  for (auto _ : state) {
    vehicle = StepQuadrotor(params, vehicle, thrust_n, external_n, step);
    benchmark::DoNotOptimize(vehicle);
  }
}
BENCHMARK(BM_QuadrotorStepHover);

}  // namespace
}  // namespace hilrig::host
