#include "rig/tactile_link_monitor.h"

#include <ostream>
#include <string>

#include "rig/check.h"

namespace hilrig::rig {
namespace {

bool HasFlag(std::uint8_t status, std::uint8_t flag) { return (status & flag) != 0; }

// A rejected frame of a node's kind is either too long/short or, for config, a bad command.
bool HasWrongLength(TactileFrameKind kind, const CanFrame& frame) {
  if (kind == TactileFrameKind::kConfig) {
    return frame.length < tactile_bus::kConfigMinLength ||
           frame.length > tactile_bus::kConfigMaxLength;
  }
  return frame.length != (kind == TactileFrameKind::kSample ? tactile_bus::kSampleLength
                                                            : tactile_bus::kStatusLength);
}

}  // namespace

Result<TactileMessage> TactileLinkMonitor::Observe(const CanFrame& frame) {
  ++bus_.frames;
  const TactileFrameKind kind = Classify(frame);
  if (kind == TactileFrameKind::kNotClassicData) ++bus_.not_classic_data;
  if (kind == TactileFrameKind::kUnknownId) ++bus_.unknown_ids;
  const std::optional<std::uint8_t> node_id = TactileNodeOf(frame, kind);

  Result<TactileMessage> message = DecodeTactileFrame(frame, kind);
  if (!node_id) return message;
  TactileNodeCounters& counters = nodes_[*node_id];
  ++counters.frames;
  if (!message) {
    CountRejected(kind, counters, frame);
    return message;
  }
  if (const auto* sample = std::get_if<TactileSample>(&message.value())) CountSample(*sample);
  if (std::holds_alternative<TactileStatus>(message.value())) ++counters.statuses;
  if (const auto* command = std::get_if<TactileConfigCommand>(&message.value())) {
    CountCommand(*command);
  }
  return message;
}

void TactileLinkMonitor::CountRejected(TactileFrameKind kind, TactileNodeCounters& counters,
                                       const CanFrame& frame) {
  if (HasWrongLength(kind, frame)) {
    ++counters.wrong_dlc;
  } else {
    ++counters.bad_commands;  // sample and status frames of the right length always decode
  }
}

void TactileLinkMonitor::CountSample(const TactileSample& sample) {
  TactileNodeCounters& counters = nodes_[sample.node_id];
  ++counters.samples;
  if (HasFlag(sample.status, tactile_bus::kSampleStale)) ++counters.stale;
  if (HasFlag(sample.status, tactile_bus::kSampleSaturated)) ++counters.saturated;
  if (HasFlag(sample.status, tactile_bus::kSampleConversionError)) ++counters.conversion_errors;

  SequenceTracker& tracker = sequences_[sample.node_id];
  if (tracker.seen) {
    const auto step = static_cast<std::uint8_t>(sample.sequence - tracker.last);
    if (step == 0) {
      ++counters.duplicates;
    } else if (step > 1) {
      ++counters.sequence_gaps;
      counters.lost_samples += step - 1u;
    }
  }
  tracker.seen = true;
  tracker.last = sample.sequence;
}

void TactileLinkMonitor::CountCommand(const TactileConfigCommand& command) {
  ++nodes_[command.node_id].commands;
  if (command.command != TactileCommand::kReset) return;
  if (command.node_id == tactile_bus::kBroadcastNodeId) {
    sequences_.fill(SequenceTracker{});
  } else {
    sequences_[command.node_id] = SequenceTracker{};
  }
}

const TactileNodeCounters& TactileLinkMonitor::node(std::uint8_t node_id) const {
  HILRIG_CHECK(node_id < kAddressCount, "tactile node id must be 0..7");
  return nodes_[node_id];
}

TactileNodeCounters TactileLinkMonitor::Totals() const {
  TactileNodeCounters total;
  for (const TactileNodeCounters& n : nodes_) {
    total.frames += n.frames;
    total.samples += n.samples;
    total.statuses += n.statuses;
    total.commands += n.commands;
    total.wrong_dlc += n.wrong_dlc;
    total.bad_commands += n.bad_commands;
    total.sequence_gaps += n.sequence_gaps;
    total.lost_samples += n.lost_samples;
    total.duplicates += n.duplicates;
    total.stale += n.stale;
    total.saturated += n.saturated;
    total.conversion_errors += n.conversion_errors;
  }
  return total;
}

std::ostream& operator<<(std::ostream& out, const TactileLinkMonitor& monitor) {
  for (std::uint8_t id = 0; id <= tactile_bus::kReferenceNodeId; ++id) {
    const TactileNodeCounters& n = monitor.node(id);
    if (n.frames == 0) continue;
    out << (id == tactile_bus::kBroadcastNodeId ? "broadcast" : "node " + std::to_string(id))
        << ": frames " << n.frames << ", samples " << n.samples << ", statuses " << n.statuses
        << ", commands " << n.commands << ", wrong dlc " << n.wrong_dlc << ", bad commands "
        << n.bad_commands << ", gaps " << n.sequence_gaps << " (" << n.lost_samples
        << " lost), duplicates " << n.duplicates << ", stale " << n.stale << ", saturated "
        << n.saturated << ", conversion errors " << n.conversion_errors << '\n';
  }
  const TactileBusCounters& bus = monitor.bus();
  return out << "bus: frames " << bus.frames << ", unknown ids " << bus.unknown_ids
             << ", not classic data " << bus.not_classic_data << '\n';
}

}  // namespace hilrig::rig
