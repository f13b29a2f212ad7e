// Benchmarks of the lockstep loop: one whole tick of the hover scenario (sensors, CAN, DUT, plant,
// trace and checks at their rates), and the hot pieces inside it. One tick is 1 ms simulated, so
// 1000x real time needs a tick under 1 µs.
#include <benchmark/benchmark.h>

#include <sstream>

#include "bench/shipped_scene.h"
#include "dut_fw/flight_controller.h"
#include "host/dut/firmware_config.h"
#include "host/dut/in_process_dut.h"
#include "host/plant/quadrotor.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/sensors/imu_emulator.h"
#include "rig/clock.h"
#include "rig/emulated_bus.h"

namespace hilrig::host {
namespace {

// A shipped scenario, run for a day: its timeline is over early and the rest is steady state.
ScenarioConfig LongRunOf(const std::string& scenario) { return ShippedScene(scenario, 86400); }

// One lockstep tick of `scenario` after `warm_up_s` of simulated time.
void TickScenario(benchmark::State& state, const std::string& scenario, double warm_up_s) {
  const ScenarioConfig config = LongRunOf(scenario);
  std::ostringstream trace, can_log;
  const rig::SteadyClock wall_clock;
  ScenarioRunner runner(config, {&trace, &can_log, nullptr}, {&wall_clock, nullptr});
  for (int i = 0; i < static_cast<int>(warm_up_s * 1000); ++i) runner.Tick();
  trace.str("");
  std::uint64_t ticks = 0;
  for (auto _ : state) {
    if (!runner.Tick()) state.SkipWithError("run ended");
    // Keep the in-memory trace from growing without bound over long benchmark runs.
    if (++ticks % 100'000 == 0) trace.str("");
  }
  state.counters["real_time_factor"] = benchmark::Counter(
      1e-3 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_LockstepTick(benchmark::State& state) { TickScenario(state, "hover", 0); }
BENCHMARK(BM_LockstepTick);

// Seven Hall sensor nodes on CAN, nothing touching the pads.
void BM_TactileHoverTick(benchmark::State& state) { TickScenario(state, "tactile_hover", 25); }
BENCHMARK(BM_TactileHoverTick);

// The balloon held at its regulated force: servo, contact, six pads through the sensor model and
// CAN, and the DUT's grasp and force-aware position loops, every tick.
void BM_BalloonGraspTick(benchmark::State& state) { TickScenario(state, "balloon_grasp", 30); }
BENCHMARK(BM_BalloonGraspTick);

void BM_QuadrotorStep(benchmark::State& state) {
  const QuadrotorParams params;
  QuadrotorState plant = MakeHoveringQuadrotor(params, Eigen::Vector3d(0, 0, 1), 0.0);
  const double hover_n = HoverThrustPerRotor(params);
  const std::array<double, 4> thrust_n = {hover_n, hover_n, hover_n, hover_n};
  for (auto _ : state) {
    plant = StepQuadrotor(params, plant, thrust_n, Eigen::Vector3d::Zero(), 1e-3);
    benchmark::DoNotOptimize(plant);
  }
}
BENCHMARK(BM_QuadrotorStep);

void BM_FlightControllerStep(benchmark::State& state) {
  const QuadrotorParams vehicle;
  const dut_fw::FlightController<double> controller(FirmwareParamsFor(vehicle));
  dut_fw::FlightControllerState<double> dut_state;
  controller.OnVio(dut_state, Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity(), 0);
  dut_fw::Reference<double> reference{Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero(),
                                      Eigen::Vector3d::Zero(), 0.0};
  std::int64_t time_ns = 0;
  for (auto _ : state) {
    time_ns += 1'000'000;
    controller.OnImu(dut_state, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 9.81), time_ns);
    benchmark::DoNotOptimize(controller.Step(dut_state, reference, Eigen::Vector3d::Zero(), 1e-3));
  }
}
BENCHMARK(BM_FlightControllerStep);

// The in-process DUT's share of one balloon_grasp tick without tactile traffic: an IMU sample, the
// setpoint (grasp regulating) and the control step, through the DutPort calls the runner makes.
void BM_DutStep(benchmark::State& state) {
  const ScenarioConfig config = LongRunOf("balloon_grasp");
  rig::EmulatedBus bus;
  InProcessDut dut(FirmwareFor(config), bus.Connect("dut"), 1e-3);
  dut.Send(VioMessage{{0, 0}, 0, Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity()});
  SetpointMessage setpoint;
  setpoint.position_m = Eigen::Vector3d(0, 0, 1);
  setpoint.yaw_rad = 0.3;
  setpoint.grasp_regulate = true;
  setpoint.grasp_force_n = 0.65;
  setpoint.grasp_reference_angle_rad = 0.5;
  std::uint64_t tick = 0;
  for (auto _ : state) {
    const std::int64_t now_ns = std::int64_t(++tick) * 1'000'000;
    dut.Send(ImuMessage{
        {tick, now_ns}, Eigen::Vector3d(0.01, -0.02, 0.005), Eigen::Vector3d(0, 0, 9.81)});
    setpoint.stamp = {tick, now_ns};
    dut.Send(setpoint);
    benchmark::DoNotOptimize(dut.Step(tick, now_ns));
  }
}
BENCHMARK(BM_DutStep);

void BM_ImuSample(benchmark::State& state) {
  const ImuParams params;
  ImuState imu = MakeImuState(params, RandomStream::FromSeed(1, 1));
  std::int64_t time_ns = 0;
  for (auto _ : state) {
    time_ns += 1'000'000;
    benchmark::DoNotOptimize(
        SampleImu(params, imu, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 9.81), time_ns));
  }
}
BENCHMARK(BM_ImuSample);

}  // namespace
}  // namespace hilrig::host

namespace hilrig::host {
namespace {

// One 1 ms step of a tumbling body with a constant torque, per integrator (the argument is the
// Integrator value: 0 semi-implicit Euler, 1 RK4, 2 midpoint, 3 Dormand-Prince at 1e-6).
void BM_RigidBodyStep(benchmark::State& state) {
  const auto integrator = static_cast<Integrator>(state.range(0));
  RigidBodyParams params;
  params.inertia_kg_m2 = {2e-3, 3e-3, 5e-3};
  Wrench wrench;
  wrench.force_world_n = {0.0, 0.0, params.mass_kg * 9.81};
  wrench.torque_body_nm = {1e-4, -2e-4, 5e-5};
  RigidBodyState body;
  body.angular_velocity_rad_s = {3.0, -1.0, 2.0};
  const RigidBodyIntegratorOptions options;
  IntegratorStats stats;
  std::uint64_t substeps = 0;
  for (auto _ : state) {
    body = StepRigidBody(params, body, wrench, 9.81, 1e-3, integrator, options, &stats);
    substeps += stats.accepted_substeps + stats.rejected_substeps;
    benchmark::DoNotOptimize(body);
  }
  state.SetLabel(IntegratorName(integrator));
  state.counters["substeps_per_step"] =
      static_cast<double>(substeps) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_RigidBodyStep)->DenseRange(0, 3);

}  // namespace
}  // namespace hilrig::host
