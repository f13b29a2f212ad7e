// The bench image: the controller proving itself on the target without a rig. It announces
// itself, runs the controller on a fixed hover-and-grasp input sequence for a number of control
// steps, timing each with SysTick, reports the work per step on USART1, and then echoes what each
// USART receives so both directions of both lines can be checked (tests/target/qemu_boot_test.sh).
// The inputs are what the rig sends a DUT hovering at 1 m with six loaded pads: IMU at 1 kHz, VIO
// at 100 Hz, every sensor node at 50 Hz.
#include <algorithm>
#include <array>
#include <cstdint>

#include "dut_fw/dut_core.h"
#include "dut_fw/serial_line_rates.h"
#include "dut_fw/target/board.h"

namespace target = hilrig::dut_fw::target;
namespace fw = hilrig::dut_fw;

namespace {

constexpr std::uint32_t kBenchSteps = 1000;
constexpr std::int64_t kControlPeriodNs = 1'000'000;
constexpr float kControlPeriodS = 1e-3f;
constexpr float kVehicleMassKg = 0.556f;

fw::TactileProcessorParams<float> BenchTactileParams() {
  fw::TactileProcessorParams<float> params;
  for (std::size_t i = 0; i < params.nodes.size(); ++i) {
    params.nodes[i].node_id = std::uint8_t(i + 1);
    params.nodes[i].gain_a = fw::Vec3<float>(0.5f, 0.5f, 2.0f);
  }
  params.film = fw::FilmConstants<float>::Published();
  params.zeroing_samples = 5;
  return params;
}

fw::DutCoreParams<float> BenchParams() {
  fw::DutCoreParams<float> params;
  params.flight = fw::DefaultFlightControllerParams<float>(kVehicleMassKg);
  params.tactile = BenchTactileParams();
  return params;
}

void FeedInputs(fw::DutCore<float>& core, std::uint32_t step, std::int64_t now_ns) {
  core.OnImu(fw::Vec3<float>::Zero(), fw::Vec3<float>(0.f, 0.f, 9.81f), now_ns);
  if (step % 10 == 0) {
    core.OnVio(fw::Vec3<float>(0.f, 0.f, 1.f), fw::Quat<float>::Identity(), now_ns);
  }
  if (step % 20 == 0) {
    const auto sequence = std::uint8_t(step / 20);
    core.OnSensorSample(hilrig::tactile_bus::kReferenceNodeId, {40, 65500, 200}, sequence, false,
                        now_ns);
    const bool loaded = step > 200;
    for (std::uint8_t node = 1; node <= hilrig::tactile_bus::kTactileNodeCount; ++node) {
      const std::uint16_t z = loaded ? std::uint16_t(9000 + 100 * node) : std::uint16_t(8000);
      core.OnSensorSample(node, {std::uint16_t(300 + node), 65000, z}, sequence, false, now_ns);
    }
  }
}

std::array<std::uint32_t, kBenchSteps> step_cycles;

void RunBench(fw::DutCore<float>& core) {
  fw::Reference<float> hover;
  hover.position_m = fw::Vec3<float>(0.f, 0.f, 1.f);
  hover.velocity_m_s.setZero();
  hover.acceleration_m_s2.setZero();
  hover.yaw_rad = 0.f;
  fw::GraspCommand<float> grasp;
  grasp.mode = fw::GraspMode::kForce;
  grasp.force_n = 0.6f;
  grasp.reference_angle_rad = 0.8f;
  core.OnSetpoint(hover, grasp);

  fw::DutCoreOutput<float> out;
  const std::uint32_t bench_start = target::CycleCount();
  for (std::uint32_t step = 0; step < kBenchSteps; ++step) {
    const std::int64_t now_ns = std::int64_t(step) * kControlPeriodNs;
    const std::uint32_t start = target::CycleCount();
    FeedInputs(core, step, now_ns);
    out = core.Step(now_ns, kControlPeriodS);
    step_cycles[step] = target::CycleCount() - start;
  }
  const std::uint32_t total_cycles = target::CycleCount() - bench_start;

  std::sort(step_cycles.begin(), step_cycles.end());
  const auto line = [](std::string_view label, std::uint32_t value) {
    target::Write(target::Port::kLink, label);
    target::WriteUnsigned(target::Port::kLink, value);
  };
  line("bench: steps ", kBenchSteps);
  line(" cycles/step p50 ", step_cycles[kBenchSteps / 2]);
  line(" p99 ", step_cycles[kBenchSteps * 99 / 100]);
  line(" max ", step_cycles.back());
  line(" total ", total_cycles);
  line(" steps/s ", std::uint32_t(std::uint64_t(kBenchSteps) * target::kCoreClockHz /
                                  std::max<std::uint32_t>(total_cycles, 1)));
  line(" armed ", out.armed ? 1 : 0);
  line(" tactile_ready ", out.tactile_ready ? 1 : 0);
  line(" servo_mrad ", std::uint32_t(std::max(0.f, out.servo_angle_rad) * 1000.f));
  line(" thrust_mN ", std::uint32_t(std::max(0.f, out.rotor_thrust_n[0]) * 1000.f));
  target::Write(target::Port::kLink, "\r\n");
}

}  // namespace

int main() {
  const target::ClockSource clock = target::InitBoard(fw::kLinkBaud, fw::kBridgeBaud);
  target::Write(target::Port::kLink, "hilrig dut_fw stm32f405: clock ");
  target::Write(target::Port::kLink, clock == target::ClockSource::kPll168MHz
                                         ? "pll 168 MHz\r\n"
                                         : "rcc not responding\r\n");
  static fw::DutCore<float> core(BenchParams());
  RunBench(core);
  target::Write(target::Port::kLink, "echo: USART1, USART2\r\n");
  for (;;) {
    for (const target::Port port : {target::Port::kLink, target::Port::kBridge}) {
      if (const auto byte = target::ReadByte(port)) {
        const char c = char(*byte);
        target::Write(port, std::string_view(&c, 1));
      }
    }
  }
}
