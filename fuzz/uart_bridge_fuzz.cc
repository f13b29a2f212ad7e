// Fuzz target for the node firmware's UART bridge decoder: the input is a raw byte stream as it
// would arrive on the UART. Properties checked beyond "does not crash": every delivered frame is
// one a classic bus can carry and re-encodes to bytes that decode to the same frame, and the
// counters never claim more frames than were delivered. Corpus: fuzz/corpus/uart_bridge.
#include <array>
#include <cstdint>

#include "dut_fw/sensor_node.h"
#include "fuzz/fuzz_target.h"

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
