// The receiving side's bookkeeping of the tactile bus: every frame a host or DUT reads goes
// through Observe, which decodes it with rig/tactile_protocol.h and counts, per node, what arrived
// and what was wrong with it -- wrong lengths, bad commands, sequence gaps and duplicates, stale
// and saturated samples -- plus, bus-wide, frames whose id is not a tactile id and frames that are
// not classic data frames at all. Corrupt input is counted and handed back as an Error, never a
// crash, so a report can show how healthy the link was instead of silently losing samples.
//
// Sequence arithmetic is modulo 256: 255 -> 0 is the normal successor, a step of k > 1 is one gap
// of k - 1 lost samples, a step of 0 is a duplicate. A node that loses 256 or more samples in a row
// therefore aliases to a shorter gap; at 50 Hz that is over 5 s of silence, which the frame
// counters show anyway. A reset command seen for a node (or broadcast) forgets its last sequence,
// because the node restarts counting at 0.
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>

#include "rig/can_frame.h"
#include "rig/result.h"
#include "rig/tactile_protocol.h"

namespace hilrig::rig {

struct TactileNodeCounters {
  std::uint64_t frames = 0;             // every frame with this node's id, good or bad
  std::uint64_t samples = 0;            // decoded sample frames
  std::uint64_t statuses = 0;           // decoded status frames
  std::uint64_t commands = 0;           // decoded config commands addressed to the node
  std::uint64_t wrong_dlc = 0;          // sample/status/config frames of the wrong length
  std::uint64_t bad_commands = 0;       // config frames with an unknown command or bad argument
  std::uint64_t sequence_gaps = 0;      // jumps in the sample sequence
  std::uint64_t lost_samples = 0;       // sequence numbers skipped by those jumps
  std::uint64_t duplicates = 0;         // the same sequence twice in a row
  std::uint64_t stale = 0;              // samples flagged tactile_bus::kSampleStale
  std::uint64_t saturated = 0;          // samples flagged tactile_bus::kSampleSaturated
  std::uint64_t conversion_errors = 0;  // samples flagged tactile_bus::kSampleConversionError

  friend bool operator==(const TactileNodeCounters&, const TactileNodeCounters&) = default;
};

struct TactileBusCounters {
  std::uint64_t frames = 0;            // everything observed
  std::uint64_t unknown_ids = 0;       // classic data frames with a non-tactile id
  std::uint64_t not_classic_data = 0;  // extended, remote, FD and error frames

  friend bool operator==(const TactileBusCounters&, const TactileBusCounters&) = default;
};

class TactileLinkMonitor {
 public:
  // Decodes and counts one frame; the Error says what was wrong with a frame that did not decode.
  Result<TactileMessage> Observe(const CanFrame& frame);

  // node_id 0 is the broadcast config address, 1..7 the nodes; aborts on anything larger.
  const TactileNodeCounters& node(std::uint8_t node_id) const;
  const TactileBusCounters& bus() const { return bus_; }
  // The per-node counters summed over every address.
  TactileNodeCounters Totals() const;

 private:
  struct SequenceTracker {
    bool seen = false;
    std::uint8_t last = 0;
  };

  void CountSample(const TactileSample& sample);
  void CountCommand(const TactileConfigCommand& command);
  void CountRejected(TactileFrameKind kind, TactileNodeCounters& counters, const CanFrame& frame);

  static constexpr std::size_t kAddressCount = tactile_bus::kReferenceNodeId + 1;
  std::array<TactileNodeCounters, kAddressCount> nodes_{};
  std::array<SequenceTracker, kAddressCount> sequences_{};
  TactileBusCounters bus_;
};

// One line per address that saw traffic plus the bus line, for logs and reports.
std::ostream& operator<<(std::ostream& out, const TactileLinkMonitor& monitor);

}  // namespace hilrig::rig
