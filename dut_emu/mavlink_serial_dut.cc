#include "dut_emu/mavlink_serial_dut.h"

#include <array>
#include <memory>

#include "host/link/open_byte_stream.h"

namespace hilrig::dut_emu {
namespace {

// A read waits at most this long, so that a stop request is seen; ten of them without a step are
// a second, when the heartbeat goes again.
constexpr int kReadSliceMs = 100;
constexpr int kSlicesPerHeartbeat = 10;
constexpr int kWriteTimeoutMs = 1000;

class SerialLoop {
 public:
  SerialLoop(std::unique_ptr<host::ByteStream> line, const std::atomic<bool>* stop,
             std::ostream& log, MavlinkDut& dut)
      : line_(std::move(line)), stop_(stop), log_(log), dut_(dut) {}

  int Run() {
    int idle_slices = 0;
    if (auto done = Deliver(dut_.Announce())) return *done;
    for (;;) {
      if (stop_ != nullptr && stop_->load()) {
        log_ << "dut_emu: stopped by a signal\n";
        return kExitOk;
      }
      const host::StreamRead read = line_->ReadSome(buffer_, kReadSliceMs);
      if (read.status == host::StreamStatus::kTimeout) {
        // Until the rig steps it, the board says it is there once a second.
        if (dut_.counters().sensor_steps == 0 && ++idle_slices == kSlicesPerHeartbeat) {
          idle_slices = 0;
          if (auto done = Deliver(dut_.Announce())) return *done;
        }
        continue;
      }
      if (read.status != host::StreamStatus::kData) return Ended(read);
      if (auto done = Take(std::span(buffer_.data(), read.bytes))) return *done;
    }
  }

 private:
  // The line ended: the rig closed it (a hung-up terminal reads as an error too).
  int Ended(const host::StreamRead& read) {
    const std::uint64_t steps = dut_.counters().sensor_steps;
    if (steps == 0) {
      log_ << "dut_emu: the line " << line_->name() << " ended before the first HIL_SENSOR"
           << (read.error.empty() ? "" : ": " + read.error) << "\n";
      return kExitFailed;
    }
    log_ << "dut_emu: the rig closed the line after " << steps << " steps\n";
    return kExitOk;
  }

  std::optional<int> Take(std::span<const std::uint8_t> bytes) {
    while (!bytes.empty()) {
      bytes = bytes.subspan(parser_.Push(bytes));
      while (std::optional<mavlink::Frame> frame = parser_.Next()) {
        if (auto done = Deliver(dut_.HandleFrame(*frame, LinkOf(frame->message_id)))) return done;
      }
      if (const std::optional<const char*> reason = DropReason(parser_.counters())) {
        log_ << "dut_emu: the line sent " << *reason << ": the codec cannot decode it\n";
        return kExitFailed;
      }
    }
    return std::nullopt;
  }

  // Both links' replies on the one line, the API link's first as on sockets.
  std::optional<int> Deliver(const MavlinkReplies& replies) {
    for (const MavlinkFrameBatch* batch : {&replies.api, &replies.simulator}) {
      for (std::size_t i = 0; i < batch->size(); ++i) {
        if (auto written = line_->WriteAll(batch->frame(i), kWriteTimeoutMs); !written) {
          log_ << "dut_emu: cannot write the line: " << written.error().message << "\n";
          return kExitFailed;
        }
      }
    }
    if (replies.end == MavlinkDutEnd::kRunning) return std::nullopt;
    log_ << "dut_emu: " << replies.why << "\n";
    return replies.end == MavlinkDutEnd::kSensorsStale ? kExitSensorsStale : kExitFailed;
  }

  std::unique_ptr<host::ByteStream> line_;
  const std::atomic<bool>* stop_;
  std::ostream& log_;
  MavlinkDut& dut_;
  mavlink::FrameParser parser_{mavlink::FindWireInfo};
  std::array<std::uint8_t, 4096> buffer_{};
};

}  // namespace

int RunMavlinkSerialDut(const MavlinkDutOptions& options, const std::atomic<bool>* stop_requested,
                        std::ostream& log, MavlinkDut& dut) {
  auto line = host::OpenSerialPort(options.serial_device, options.baud);
  if (!line) {
    log << "dut_emu: " << line.error().message << "\n";
    return kExitFailed;
  }
  return SerialLoop(std::move(line).value(), stop_requested, log, dut).Run();
}

}  // namespace hilrig::dut_emu
