// vcan_exchange: a short sensor-bus exchange through a real kernel CAN interface, run by the vm
// test inside QEMU. Seven emulated sensor nodes (six tactile, one reference) each send one
// magnetometer sample frame per round through one SocketCanBus; a "DUT" SocketCanBus, filtered to
// the sample ids like the flight controller's front end, receives, decodes and checks them and
// answers each round with a command frame the node side must receive. Every frame is printed in
// candump -l form with its kernel timestamp, so the log shows the traffic crossing the kernel.
//
// Usage: vcan_exchange [interface] [rounds]. Exit 0 when every frame arrived intact and in order,
// 1 when anything was lost or corrupted, 2 when the interface cannot be opened.
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "rig/candump_log.h"
#include "rig/socketcan_bus.h"
#include "rig/tactile_protocol.h"

namespace hilrig::rig {
namespace {

constexpr std::uint32_t kDutCommandId = 0x080;  // higher priority than samples, like a command
constexpr std::int64_t kWaitSliceNs = 200'000'000;
constexpr int kMaxWaitSlices = 25;  // bounds each wait at 5 s; vcan answers in microseconds

// Deterministic codes that differ per node and round, so a swapped or stale frame is caught.
TactileSample SampleFor(std::uint8_t node_id, int round) {
  TactileSample sample;
  sample.node_id = node_id;
  sample.code = {static_cast<std::uint16_t>(100 * node_id + round),
                 static_cast<std::uint16_t>(-50 * node_id - round),
                 static_cast<std::uint16_t>(-12000 + 7 * round)};
  sample.sequence = static_cast<std::uint8_t>(round);
  return sample;
}

// Waits (bounded) until `count` frames have arrived on `bus`.
std::vector<TimedCanFrame> ReceiveFrames(SocketCanBus& bus, std::size_t count) {
  std::vector<TimedCanFrame> out;
  for (int slice = 0; slice < kMaxWaitSlices && out.size() < count; ++slice) {
    bus.Receive(0, out);
    if (out.size() < count) bus.WaitReadable(kWaitSliceNs);
  }
  return out;
}

int Run(const std::string& interface, int rounds) {
  Result<std::unique_ptr<SocketCanBus>> nodes = OpenSocketCan(interface);
  const std::array<CanFilter, 1> sample_ids = {CanFilter{
      .id = tactile_bus::kSampleBaseId, .mask = 0x7F0, .extended = false, .inverted = false}};
  Result<std::unique_ptr<SocketCanBus>> dut =
      OpenSocketCan(interface, {.filters = {sample_ids.begin(), sample_ids.end()}});
  if (!nodes.ok() || !dut.ok()) {
    std::printf("vcan_exchange: %s\n", (nodes.ok() ? dut.error() : nodes.error()).message.c_str());
    return 2;
  }
  SocketCanBus& node_bus = *nodes.value();
  SocketCanBus& dut_bus = *dut.value();

  int mismatches = 0;
  std::int64_t first_ns = 0;
  std::int64_t last_ns = 0;
  std::uint64_t samples_decoded = 0;
  for (int round = 0; round < rounds; ++round) {
    for (std::uint8_t node = tactile_bus::kFirstNodeId; node <= tactile_bus::kReferenceNodeId;
         ++node) {
      const CanFrame frame = EncodeTactileSample(SampleFor(node, round));
      if (Result<void> sent = node_bus.Send(frame, 0); !sent) {
        std::printf("vcan_exchange: send failed: %s\n", sent.error().message.c_str());
        return 1;
      }
    }
    const std::vector<TimedCanFrame> samples =
        ReceiveFrames(dut_bus, tactile_bus::kReferenceNodeId);
    if (samples.size() != tactile_bus::kReferenceNodeId) {
      std::printf("vcan_exchange: round %d: DUT received %zu of %d sample frames\n", round,
                  samples.size(), tactile_bus::kReferenceNodeId);
      return 1;
    }
    for (std::size_t i = 0; i < samples.size(); ++i) {
      std::printf("RX dut   %s\n", FormatCandumpLine(samples[i], interface).c_str());
      const Result<TactileSample> decoded = DecodeTactileSample(samples[i].frame);
      const auto expected_node = static_cast<std::uint8_t>(tactile_bus::kFirstNodeId + i);
      if (!decoded.ok() || !(decoded.value() == SampleFor(expected_node, round))) {
        std::printf("vcan_exchange: round %d node %d: frame does not decode to what was sent\n",
                    round, expected_node);
        ++mismatches;
      } else {
        ++samples_decoded;
      }
      if (first_ns == 0) first_ns = samples[i].time_ns;
      last_ns = samples[i].time_ns;
    }

    const CanFrame command = CanFrame::Classic(
        kDutCommandId, std::array<std::uint8_t, 2>{static_cast<std::uint8_t>(round), 0x01});
    if (Result<void> sent = dut_bus.Send(command, 0); !sent) {
      std::printf("vcan_exchange: DUT send failed: %s\n", sent.error().message.c_str());
      return 1;
    }
    const std::vector<TimedCanFrame> commands = ReceiveFrames(node_bus, 1);
    if (commands.size() != 1 || !(commands[0].frame == command)) {
      std::printf("vcan_exchange: round %d: nodes did not receive the DUT command\n", round);
      return 1;
    }
    std::printf("RX nodes %s\n", FormatCandumpLine(commands[0], interface).c_str());
  }

  const BusCounters node_counters = node_bus.counters();
  const BusCounters dut_counters = dut_bus.counters();
  std::printf(
      "vcan_exchange: %d rounds on %s: nodes sent %llu, DUT received %llu and decoded %llu, "
      "DUT sent %llu, nodes received %llu; kernel timestamps span %lld us; %d mismatches\n",
      rounds, interface.c_str(), static_cast<unsigned long long>(node_counters.frames_sent),
      static_cast<unsigned long long>(dut_counters.frames_received),
      static_cast<unsigned long long>(samples_decoded),
      static_cast<unsigned long long>(dut_counters.frames_sent),
      static_cast<unsigned long long>(node_counters.frames_received),
      static_cast<long long>((last_ns - first_ns) / 1000), mismatches);
  const bool ok = mismatches == 0 &&
                  node_counters.frames_sent == static_cast<std::uint64_t>(7 * rounds) &&
                  dut_counters.frames_received == node_counters.frames_sent &&
                  node_counters.frames_received == static_cast<std::uint64_t>(rounds);
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace hilrig::rig

int main(int argc, char** argv) {
  const std::string interface = argc > 1 ? argv[1] : "vcan0";
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 10;
  return hilrig::rig::Run(interface, rounds);
}
