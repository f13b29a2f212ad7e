// Benchmarks of the per-row and per-frame text the lockstep tick writes: one trace.csv row (36
// columns, most of them changing from row to row like a flight's) and one candump line.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <sstream>
#include <streambuf>

#include "host/trace/significant_decimal.h"
#include "host/trace/trace_csv.h"
#include "rig/candump_log.h"

namespace hilrig::host {
namespace {

// Discards what it is given, so the benchmark measures formatting and not a growing string.
class NullBuffer : public std::streambuf {
 protected:
  std::streamsize xsputn(const char*, std::streamsize count) override { return count; }
  int overflow(int c) override { return c; }
};

// A grasp scene's row at tick `row`: a moving vehicle, a fixed reference, forces that change.
TraceSample FlightSample(int row) {
  const double t = row * 0.01;
  TraceSample s;
  s.time_s = t;
  s.position_m = {0.1 * std::sin(t), 0.05 * std::cos(1.3 * t), 1.0 + 0.01 * std::sin(7 * t)};
  s.reference_m = {0, 0, 1};
  s.velocity_m_s = {0.1 * std::cos(t), -0.065 * std::sin(1.3 * t), 0.07 * std::cos(7 * t)};
  s.roll_pitch_yaw_deg = {0.3 * std::sin(3 * t), -0.2 * std::cos(2 * t), 1e-3 * t};
  s.tilt_deg = 0.36 + 0.01 * std::sin(t);
  for (int i = 0; i < 4; ++i) s.rotor_thrust_n[i] = 2.45 + 0.01 * std::sin(t + i);
  s.estimated_position_m = s.position_m + Eigen::Vector3d(1e-4, -2e-4, 3e-5);
  s.tactile_force_max_n = 0.8 + 0.05 * std::sin(5 * t);
  s.tactile_force_error_max_n = 0.01 * std::abs(std::cos(3 * t));
  s.grasp_force_n = 1.2 + 0.02 * std::sin(2 * t);
  s.grasp_force_estimate_n = 1.21 + 0.02 * std::sin(2 * t);
  s.grasp_force_setpoint_n = 1.2;
  s.load_n = 0.49 + 1e-3 * std::sin(t);
  s.load_estimate_n = 0.5;
  s.object_mass_kg = 0.05;
  s.servo_angle_rad = 0.61 + 1e-4 * std::sin(t);
  s.servo_command_rad = 0.6;
  return s;
}

void BM_TraceRowFormat(benchmark::State& state) {
  constexpr int kRows = 256;
  std::array<TraceSample, kRows> samples;
  for (int i = 0; i < kRows; ++i) samples[i] = FlightSample(i);
  NullBuffer buffer;
  std::ostream out(&buffer);
  TraceCsvWriter writer(out);
  int row = 0;
  for (auto _ : state) {
    writer.Write(samples[row]);
    row = (row + 1) % kRows;
  }
}
BENCHMARK(BM_TraceRowFormat);

void BM_SignificantDecimal(benchmark::State& state) {
  const TraceSample sample = FlightSample(123);
  const std::array<double, 4> values = {sample.time_s, sample.position_m.x(),
                                        sample.velocity_m_s.y(), sample.grasp_force_n};
  std::array<char, kMaxSignificantDecimalChars> text;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(WriteSignificantDecimal(values[i], text.data()));
    benchmark::ClobberMemory();
    i = (i + 1) % values.size();
  }
}
BENCHMARK(BM_SignificantDecimal);

// A Hall node's 8-byte frame at a realistic log time, written as the runner's log writer does.
void BM_CandumpLine(benchmark::State& state) {
  const std::array<std::uint8_t, 8> data = {0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC, 0xDE, 0xF0};
  rig::TimedCanFrame frame{rig::CanFrame::Classic(0x231, data), 1'700'000'000'000'000'000};
  NullBuffer buffer;
  std::ostream out(&buffer);
  rig::CandumpLogWriter writer(out);
  for (auto _ : state) {
    writer.Write(frame);
    frame.time_ns += 142'857;
  }
}
BENCHMARK(BM_CandumpLine);

}  // namespace
}  // namespace hilrig::host
