// The grasp plant per physics tick: servo equilibrium and motion against the grasp's load, then
// the pad/object contact, for a balloon held at its regulated force and for a stiff glass cup.
#include <benchmark/benchmark.h>

#include "fixtures/objects/object_fixtures.h"
#include "host/plant/grasp_contact.h"
#include "host/plant/servo.h"

namespace hilrig::host {
namespace {

void GraspStep(benchmark::State& state, const char* fixture, double per_pad_force_n) {
  GraspSceneParams scene;
  scene.object = fixtures::ObjectFixture(fixture).value();
  const ServoParams servo;
  GraspState grasp = InitialGraspState(scene);
  GraspVehicleSample vehicle;
  vehicle.position_m = Eigen::Vector3d(0, 0, scene.stand_height_m);
  ServoState servo_state;
  // Close on the object still on its stand until the servo, lagging under the load, settles at
  // `per_pad_force_n` per pad; then take the stand away so the pads hold it.
  double command_rad = AngleForPadRadius(scene.frame, scene.object.half_width_m);
  GraspForces forces;
  while (forces.normal_force_n[0] < per_pad_force_n && command_rad < servo.max_angle_rad) {
    command_rad += 1e-3;
    for (int i = 0; i < 300; ++i) {
      servo_state = StepServo(servo, servo_state, command_rad, GraspServoLoad(scene, grasp), 1e-3);
      forces = StepGrasp(scene, grasp, vehicle, servo_state.angle_rad, 1e-3);
    }
  }
  scene.stand_present = false;
  // As the gripper scene steps it: the scene's constants once, the servo's decay once.
  const GraspSceneConstants constants = MakeGraspSceneConstants(scene);
  const double decay = ServoLagDecay(servo, 1e-3);
  std::uint64_t i = 0;
  for (auto _ : state) {
    // A command that wanders by a few microradians, as the DUT's does.
    const double wobble_rad = 1e-5 * static_cast<double>(++i % 7);
    servo_state = StepServoWithDecay(servo, servo_state, command_rad + wobble_rad,
                                     GraspServoLoad(scene, constants, grasp), 1e-3, decay);
    benchmark::DoNotOptimize(
        StepGrasp(scene, constants, grasp, vehicle, servo_state.angle_rad, 1e-3));
  }
  if (grasp.mode != GraspMode::kHeld) state.SkipWithError("the object is not held");
}

void BM_GraspStepBalloon(benchmark::State& state) { GraspStep(state, "balloon", 0.1); }
BENCHMARK(BM_GraspStepBalloon);
void BM_GraspStepGlassCup(benchmark::State& state) { GraspStep(state, "glass_cup", 0.6); }
BENCHMARK(BM_GraspStepGlassCup);

}  // namespace
}  // namespace hilrig::host
