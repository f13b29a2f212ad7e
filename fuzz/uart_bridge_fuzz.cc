// Fuzz target for the node firmware's UART bridge decoder: the input is a raw byte stream as it
// would arrive on the UART. Properties checked beyond "does not crash": every delivered frame is
// one a classic bus can carry and re-encodes to bytes that decode to the same frame, and the
// counters never claim more frames than were delivered.
#include <array>
#include <cstdint>

#include "dut_fw/sensor_node.h"
#include "fuzz/fuzz_seeds.h"

namespace {

using hilrig::dut_fw::NodeFrame;

void Require(bool condition) {
  if (!condition) __builtin_trap();
}

void CheckRoundTrip(const NodeFrame& frame) {
  using namespace hilrig::dut_fw;
  Require(frame.id <= 0x7FF && frame.len <= 8);
  std::array<std::uint8_t, kUartMaxFrameBytes> bytes{};
  const std::size_t size = EncodeUartFrame(frame, bytes);
  Require(size == 6u + frame.len);
  UartDecoder decoder;
  std::optional<NodeFrame> again;
  for (std::size_t i = 0; i < size; ++i) again = decoder.Feed(bytes[i]);
  Require(again.has_value() && *again == frame);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  hilrig::dut_fw::UartDecoder decoder;
  std::uint32_t delivered = 0;
  for (std::size_t i = 0; i < size; ++i) {
    if (const std::optional<NodeFrame> frame = decoder.Feed(data[i])) {
      ++delivered;
      CheckRoundTrip(*frame);
    }
  }
  Require(decoder.counters().frames == delivered);
  Require(decoder.counters().skipped_bytes <= size);
  return 0;
}

extern "C" std::size_t HilrigFuzzSeed(unsigned index, std::uint8_t* out, std::size_t capacity) {
  using namespace hilrig::dut_fw;
  if (index >= 3) return 0;
  // Seed i: i + 1 back-to-back frames of growing length.
  std::size_t used = 0;
  for (unsigned f = 0; f <= index; ++f) {
    NodeFrame frame;
    frame.id = static_cast<std::uint16_t>(0x101 + f);
    frame.len = static_cast<std::uint8_t>(2 + 3 * f);
    for (std::size_t b = 0; b < frame.len; ++b) frame.data[b] = static_cast<std::uint8_t>(b * 37);
    std::array<std::uint8_t, kUartMaxFrameBytes> bytes{};
    const std::size_t size = EncodeUartFrame(frame, bytes);
    if (used + size > capacity) break;
    for (std::size_t b = 0; b < size; ++b) out[used++] = bytes[b];
  }
  return used;
}
