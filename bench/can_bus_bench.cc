// Benchmarks of the CAN backends: frames per second through the emulated bus (one Send and one
// Receive per frame between two endpoints, the lockstep runner's pattern; the aim is 5 M/s) and
// through the loopback UDP bus, plus the seven-node tactile bus at 1 kHz per node, whose counters
// report the bus load and the arbitration latency of the lowest-priority node.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rig/emulated_bus.h"
#include "rig/udp_bus.h"

namespace hilrig::rig {
namespace {

const CanFrame kSample = CanFrame::Classic(0x101, std::array<std::uint8_t, 8>{1, 2, 3, 4, 5, 6, 7});

// One frame per 200 µs keeps a 1 Mbit/s bus below saturation, so queues stay bounded.
constexpr std::int64_t kFramePeriodNs = 200'000;

void BM_EmulatedBusFrames(benchmark::State& state) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  std::vector<TimedCanFrame> received;
  received.reserve(16);
  std::int64_t now_ns = 0;
  std::uint64_t frames = 0;
  for (auto _ : state) {
    if (!sender->Send(kSample, now_ns).ok()) state.SkipWithError("send refused");
    now_ns += kFramePeriodNs;
    received.clear();
    frames += receiver->Receive(now_ns, received);
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_EmulatedBusFrames);

void BM_UdpBusFrames(benchmark::State& state) {
  auto group = OpenUdpBusGroup(2);
  if (!group) {
    state.SkipWithError(group.error().message.c_str());
    return;
  }
  std::vector<std::unique_ptr<UdpBus>>& pair = group.value();
  std::vector<TimedCanFrame> received;
  received.reserve(16);
  std::int64_t now_ns = 0;
  std::uint64_t frames = 0;
  for (auto _ : state) {
    if (!pair[0]->Send(kSample, now_ns).ok()) state.SkipWithError("send refused");
    now_ns += kFramePeriodNs;
    received.clear();
    frames += pair[1]->Receive(now_ns, received);
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
  state.counters["malformed"] = static_cast<double>(pair[1]->counters().frames_dropped_malformed);
}
BENCHMARK(BM_UdpBusFrames);

// Seven tactile nodes (ids 0x101..0x107) sampling together at 1 kHz on 1 Mbit/s for 1 s of bus
// time. The asserted version of this scenario is EmulatedBusLoadTest in tests/rig.
void BM_SevenNodesAt1kHz(benchmark::State& state) {
  constexpr int kNodes = 7;
  constexpr std::int64_t kPeriodNs = 1'000'000;
  constexpr std::int64_t kDurationNs = 1'000'000'000;
  EmulatedBusStats stats;
  for (auto _ : state) {
    EmulatedBus bus;
    std::vector<std::unique_ptr<CanBus>> nodes;
    for (int k = 0; k < kNodes; ++k) nodes.push_back(bus.Connect("node" + std::to_string(k)));
    for (std::int64_t t = 0; t < kDurationNs; t += kPeriodNs) {
      for (int k = 0; k < kNodes; ++k) {
        if (!nodes[k]->Send(CanFrame::Classic(0x101 + k, kSample.payload()), t).ok()) {
          state.SkipWithError("send refused");
        }
      }
    }
    bus.AdvanceTo(kDurationNs + kPeriodNs);
    stats = bus.stats();
  }
  const IdQueueingStats* lowest = stats.QueueingFor(0x107);
  state.counters["load"] = stats.LoadOver(kDurationNs);
  state.counters["node7_max_latency_us"] = lowest ? 1e-3 * lowest->max_queueing_ns : -1.0;
  state.counters["node7_mean_latency_us"] = lowest ? 1e-3 * lowest->mean_queueing_ns() : -1.0;
}
BENCHMARK(BM_SevenNodesAt1kHz)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hilrig::rig
