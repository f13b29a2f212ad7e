// Reads and writes CAN traffic in the `candump -l` log format, so rig traces open directly in
// can-utils (log2asc, canplayer), python-can and SavvyCAN, and recorded bench logs can be replayed
// into emulated runs. One frame per line:
//
//   (1700000000.123456) can0 123#DEADBEEF       standard data frame (3 hex digit id)
//   (1700000000.123456) can0 1ABCDEF0#00        extended data frame (8 hex digit id)
//   (1700000000.123456) can0 123#R  / 123#R5    remote frame, requested length suffix if > 0
//   (1700000000.123456) can0 123##1DEADBEEF     CAN FD, flags nibble BRS=1 ESI=2 before the data
//   (1700000000.123456) can0 20000004#0000...   error frame: CAN_ERR_FLAG | class bits, 8 digits
//
// The writer follows can-utils' sprint_canframe byte for byte (uppercase hex, no separators).
// The parser accepts what can-utils' parse_canframe accepts: '.' between data bytes, lowercase
// hex, the FDF flag (4) in the FD flags nibble, and a trailing R/T direction token from
// `candump -x`, which the writer can add too (DirectionMark).
#pragma once

#include <cstdint>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <utility>

#include "rig/can_bus.h"
#include "rig/can_frame.h"
#include "rig/result.h"

namespace hilrig::rig {

// Whether a line ends with the direction token of `candump -x` (and python-can's writer): " T" for
// a frame this node sent (tx_echo), " R" for one it received. Parsing sets tx_echo from it.
enum class DirectionMark { kNone, kRxTx };

// Without a trailing newline. time_ns must be >= 0: log timestamps are unsigned.
std::string FormatCandumpLine(const TimedCanFrame& frame, std::string_view interface_name);
// Same, appended to `out`, so a caller can reuse one buffer and avoid per-line allocation.
void AppendCandumpLine(const TimedCanFrame& frame, std::string_view interface_name,
                       std::string& out, DirectionMark mark = DirectionMark::kNone);

// The inverse of FormatCandumpLine: returns the frame and the interface name. A trailing newline
// is ignored. Errors name what was wrong with the line, never quote it.
Result<std::pair<TimedCanFrame, std::string>> ParseCandumpLine(std::string_view line);

// Writes one line per frame to a stream it does not own; the lines are built in a reused buffer.
class CandumpLogWriter {
 public:
  CandumpLogWriter(std::ostream& out, std::string interface_name = "can0",
                   DirectionMark mark = DirectionMark::kNone);
  void Write(const TimedCanFrame& frame) { WriteAll(std::span(&frame, 1)); }
  // The frames' lines in order, handed to the stream in one piece (a unitbuf stream is flushed
  // once, after them). Aborts on an invalid frame, as Write does.
  void WriteAll(std::span<const TimedCanFrame> frames);
  std::uint64_t frames_written() const;

 private:
  std::ostream& out_;
  std::string interface_name_;
  DirectionMark mark_;
  // The timestamp's seconds part and " name " of the last line, from which each line starts.
  std::string prefix_;
  std::uint64_t seconds_in_prefix_ = UINT64_MAX;  // whose digits prefix_ holds; none at first
  std::string lines_;                             // grows to the longest batch, then is reused
  std::uint64_t frames_written_ = 0;
};

}  // namespace hilrig::rig
