// A run's DUT traffic read back from its log (host/replay/dut_traffic_log.h): which channel
// carries what, and each message decoded into what the runner exchanged with the DUT (an input, a
// CAN frame, a step asked, a command answered). Decoding is per message, as a replay goes, so
// memory stays the log's payloads.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>

#include "host/link/hil_messages.h"
#include "host/mcap/mcap_reader.h"
#include "proto/run_log.pb.h"
#include "rig/can_bus.h"
#include "rig/result.h"

namespace hilrig::host {

struct RecordedStep {
  std::uint64_t tick = 0;
  std::int64_t time_ns = 0;  // simulated, from the run's start
};

struct RecordedCommand {
  std::uint64_t tick = 0;  // the control tick it answers
  std::int64_t time_ns = 0;
  ActuatorMessage command;
};

using RecordedEvent = std::variant<DutInput, rig::TimedCanFrame, RecordedStep, RecordedCommand>;

class RecordedTraffic {
 public:
  // The log's recording (its spec) and its traffic channels. Fails, naming what is missing, on a
  // log without /run/recording (not a run's log, or one written without its DUT's traffic) or
  // with a traffic channel whose schema is not the one the rig writes.
  static rig::Result<RecordedTraffic> Of(const mcap::McapContents& contents);

  const proto::RunRecording& recording() const { return recording_; }

  // The event `message` records; nullopt for a message on another channel (the plant's, the
  // checks', ...). Fails on a payload that does not parse or a CAN frame that cannot be one.
  // Allocates the decoded message only.
  rig::Result<std::optional<RecordedEvent>> Decode(const mcap::McapMessage& message) const;

 private:
  enum class Kind { kInput, kCan, kStep, kCommand };
  struct Channel {
    Kind kind = Kind::kInput;
    std::size_t input_index = 0;  // kInput: the DutInput alternative
  };
  proto::RunRecording recording_;
  std::map<std::uint16_t, Channel> channels_;
};

}  // namespace hilrig::host
