#include "rig/candump_replay.h"

#include <algorithm>
#include <cmath>

#include "rig/bounded_line.h"
#include "rig/candump_log.h"

namespace hilrig::rig {

Result<CandumpReplay> CandumpReplay::Read(std::istream& log, double speed) {
  if (!(speed > 0) || !std::isfinite(speed)) return MakeError("replay speed must be > 0");
  std::vector<TimedCanFrame> frames;
  std::string line;
  for (int line_number = 1;; ++line_number) {
    const LineRead read = ReadBoundedLine(log, kMaxCandumpLineBytes, line);
    if (read == LineRead::kEnd) break;
    if (read == LineRead::kReadError) {
      return MakeError("cannot read the log after line " + std::to_string(line_number - 1));
    }
    if (read == LineRead::kTooLong) {
      return MakeError("line " + std::to_string(line_number) + ": longer than " +
                       std::to_string(kMaxCandumpLineBytes) + " bytes, not a candump line");
    }
    if (line.empty() || line[0] == '#') continue;
    auto parsed = ParseCandumpLine(line);
    if (!parsed) {
      return MakeError("line " + std::to_string(line_number) + ": " + parsed.error().message);
    }
    frames.push_back(parsed.value().first);
  }
  if (!frames.empty()) {
    const std::int64_t first_ns = frames.front().time_ns;
    for (TimedCanFrame& frame : frames) frame.time_ns -= first_ns;
    // A log is in time order; a frame stamped earlier than its predecessor goes out right after it.
    for (std::size_t i = 1; i < frames.size(); ++i) {
      frames[i].time_ns = std::max(frames[i].time_ns, frames[i - 1].time_ns);
    }
  }
  return CandumpReplay(std::move(frames), speed);
}

CandumpReplay::CandumpReplay(std::vector<TimedCanFrame> frames, double speed)
    : frames_(std::move(frames)), speed_(speed) {}

std::size_t CandumpReplay::Tick(std::int64_t now_ns, CanBus& bus) {
  if (!started_) {
    started_ = true;
    start_ns_ = now_ns;
  }
  const double elapsed_recorded_ns = static_cast<double>(now_ns - start_ns_) * speed_;
  std::size_t sent = 0;
  while (next_ < frames_.size() &&
         static_cast<double>(frames_[next_].time_ns) <= elapsed_recorded_ns) {
    if (bus.Send(frames_[next_].frame, now_ns).ok()) {
      ++sent;
    } else {
      ++send_failures_;
    }
    ++next_;
  }
  return sent;
}

}  // namespace hilrig::rig
