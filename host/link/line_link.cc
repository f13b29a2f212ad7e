#include "host/link/line_link.h"

#include "host/link/poll_wait.h"

namespace hilrig::host {

std::vector<rig::Metric> LineLinkMetrics(const LineLinkCounters& counters,
                                         const std::string& prefix) {
  const auto d = [](std::uint64_t value) { return static_cast<double>(value); };
  return {{prefix + "frames_sent", d(counters.frames_sent)},
          {prefix + "bytes_sent", d(counters.bytes_sent)},
          {prefix + "frames_received", d(counters.frames_received)},
          {prefix + "bytes_received", d(counters.bytes_received)},
          {prefix + "bad_checksum", d(counters.bad_checksum)},
          {prefix + "malformed", d(counters.malformed)},
          {prefix + "oversize", d(counters.oversize)}};
}

LineLink::LineLink(ByteStream& stream) : stream_(stream) {}

const LineLinkCounters& LineLink::counters() const {
  const dut_link::FrameDecoderCounters& decoded = decoder_.counters();
  counters_.bad_checksum = decoded.bad_checksums;
  counters_.malformed = decoded.malformed + unparsed_;
  counters_.oversize = decoded.oversize;
  return counters_;
}

rig::Result<void> LineLink::Send(const proto::LinkMessage& message, int timeout_ms,
                                 bool flush_first) {
  const std::size_t payload_bytes = message.ByteSizeLong();
  if (payload_bytes > dut_link::kMaxLineMessageBytes) {
    return rig::MakeError("a " + std::to_string(payload_bytes) +
                          "-byte message is over the serial link's limit of " +
                          std::to_string(dut_link::kMaxLineMessageBytes) + " bytes");
  }
  std::string payload;
  message.SerializeToString(&payload);
  const std::size_t lead = flush_first ? 1 : 0;
  encoded_.assign(lead + dut_link::EncodedFrameBytes(payload.size()), dut_link::kFrameDelimiter);
  const std::size_t size = dut_link::EncodeFrame(
      std::span(reinterpret_cast<const std::uint8_t*>(payload.data()), payload.size()),
      std::span(encoded_).subspan(lead));
  encoded_.resize(lead + size);
  if (auto written = stream_.WriteAll(encoded_, timeout_ms); !written) return written.error();
  ++counters_.frames_sent;
  counters_.bytes_sent += encoded_.size();
  return {};
}

bool LineLink::TakeBuffered(proto::LinkMessage& message) {
  while (chunk_at_ < chunk_size_) {
    const auto payload = decoder_.Feed(chunk_[chunk_at_++]);
    if (!payload) continue;
    if (!message.ParseFromArray(payload->data(), static_cast<int>(payload->size()))) {
      ++unparsed_;
      continue;
    }
    ++counters_.frames_received;
    return true;
  }
  return false;
}

LineReceived LineLink::Receive(int timeout_ms) {
  const Deadline deadline = DeadlineIn(timeout_ms);
  LineReceived received;
  // The first read waits the whole timeout: a stream whose waits cost no wall time (a test's) sees
  // the timeout it was given, not what the wall clock left of it.
  bool first_read = true;
  while (true) {
    if (TakeBuffered(received.message)) {
      received.status = LineReceiveStatus::kMessage;
      return received;
    }
    const StreamRead read =
        stream_.ReadSome(chunk_, first_read ? timeout_ms : MillisecondsLeft(deadline));
    first_read = false;
    switch (read.status) {
      case StreamStatus::kData:
        chunk_size_ = read.bytes;
        chunk_at_ = 0;
        counters_.bytes_received += read.bytes;
        continue;
      case StreamStatus::kTimeout:
        return received;
      case StreamStatus::kClosed:
        received.status = LineReceiveStatus::kClosed;
        received.error = read.error;
        return received;
      case StreamStatus::kError:
        received.status = LineReceiveStatus::kError;
        received.error = read.error;
        return received;
    }
  }
}

}  // namespace hilrig::host
