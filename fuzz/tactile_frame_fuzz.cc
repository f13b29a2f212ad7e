// Fuzz target for the rig's tactile frame decoders and link monitor: the input is one CanFrame
// with arbitrary flags, id, length (including lengths no bus carries) and data. Properties checked
// beyond "does not crash": a frame that decodes re-encodes to the same frame, and the monitor
// files every frame in exactly one bucket. Corpus: fuzz/corpus/tactile_frame.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <variant>

#include "fuzz/fuzz_target.h"
#include "rig/tactile_link_monitor.h"
#include "rig/tactile_protocol.h"

namespace {

using hilrig::rig::CanFrame;

// Input: flags byte, id (2 bytes LE), length byte, then data.
CanFrame FrameFromBytes(const std::uint8_t* data, std::size_t size) {
  CanFrame frame;
  if (size < 4) return frame;
  frame.extended = (data[0] & 0x01) != 0;
  frame.remote = (data[0] & 0x02) != 0;
  frame.fd = (data[0] & 0x04) != 0;
  frame.error = (data[0] & 0x08) != 0;
  frame.bitrate_switch = (data[0] & 0x10) != 0;
  frame.id = static_cast<std::uint32_t>(data[1] | (data[2] << 8));
  frame.length = data[3];
  std::memcpy(frame.data.data(), data + 4, std::min(size - 4, frame.data.size()));
  return frame;
}

void Require(bool condition) {
  if (!condition) __builtin_trap();
}

bool SameClassicFrame(const CanFrame& a, const CanFrame& b) {
  return a.id == b.id && a.length == b.length && a.length <= 8 &&
         std::memcmp(a.data.data(), b.data.data(), a.length) == 0;
}

void CheckReencodes(const CanFrame& frame, const hilrig::rig::TactileMessage& message) {
  using namespace hilrig::rig;
  if (const auto* sample = std::get_if<TactileSample>(&message)) {
    Require(SameClassicFrame(EncodeTactileSample(*sample), frame));
  } else if (const auto* status = std::get_if<TactileStatus>(&message)) {
    Require(SameClassicFrame(EncodeTactileStatus(*status), frame));
  } else {
    // Config frames may be shorter than 8 bytes and carry reserved bytes: compare the meaning.
    const auto& command = std::get<TactileConfigCommand>(message);
    const Result<TactileConfigCommand> again = DecodeTactileConfig(EncodeTactileConfig(command));
    Require(again.ok() && again.value() == command);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hilrig::rig;
  const CanFrame frame = FrameFromBytes(data, size);
  (void)Classify(frame);
  (void)TactileNodeOf(frame);
  const Result<TactileMessage> decoded = DecodeTactileFrame(frame);
  if (decoded.ok()) {
    CheckReencodes(frame, decoded.value());
  } else {
    Require(!decoded.error().message.empty());
  }
  TactileLinkMonitor monitor;
  (void)monitor.Observe(frame);
  (void)monitor.Observe(frame);  // the second one exercises the duplicate path
  Require(monitor.bus().frames == 2);
  Require(monitor.Totals().frames + monitor.bus().unknown_ids + monitor.bus().not_classic_data ==
          2);
  return 0;
}
