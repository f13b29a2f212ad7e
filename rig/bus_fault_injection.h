// Fault injection for emulated CAN media: which frames get lost or corrupted on the wire, drawn
// from one seeded stream so that a faulty run is as reproducible as a clean one. The generator is
// spelled out (SplitMix64) rather than taken from <random>, whose distributions differ between
// standard libraries and would make the same seed fail different frames on different machines.
#pragma once

#include <cstdint>

#include "rig/check.h"

namespace hilrig::rig {

// Per transmitted data or remote frame (error frames are never faulted):
//  - drop: the frame occupies the wire and its sender sees it sent (and echoed), but no other
//    endpoint receives it, like a frame every receiver's controller missed.
//  - corrupt: one bit flips on the wire. CAN's 15-bit CRC detects every single-bit error, so the
//    frame is never delivered with the flipped bit: every node raises an error flag (receivers
//    get a protocol error frame at the CRC sequence), the sender's TEC rises by 8 and each
//    receiver's REC by 1, and the sender retransmits automatically, as real controllers do.
//    Persistent corruption therefore walks the sender through error-passive into bus-off.
struct BusFaultConfig {
  std::uint64_t seed = 0;
  double drop_probability = 0.0;
  double corrupt_probability = 0.0;

  bool enabled() const { return drop_probability > 0.0 || corrupt_probability > 0.0; }
};

enum class WireFault { kNone, kDrop, kCorrupt };

// Draws exactly one number per frame, so the fate of frame k depends only on the seed and k.
class FaultStream {
 public:
  explicit FaultStream(const BusFaultConfig& config) : config_(config), state_(config.seed) {
    HILRIG_CHECK(config.drop_probability >= 0.0 && config.corrupt_probability >= 0.0 &&
                     config.drop_probability + config.corrupt_probability <= 1.0,
                 "fault probabilities must be >= 0 and sum to at most 1");
  }

  WireFault Next() {
    if (!config_.enabled()) return WireFault::kNone;
    const double u = NextUniform();
    if (u < config_.corrupt_probability) return WireFault::kCorrupt;
    if (u < config_.corrupt_probability + config_.drop_probability) return WireFault::kDrop;
    return WireFault::kNone;
  }

 private:
  // Uniform in [0, 1) with 53 random bits.
  double NextUniform() {
    state_ += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }

  BusFaultConfig config_;
  std::uint64_t state_;
};

}  // namespace hilrig::rig
