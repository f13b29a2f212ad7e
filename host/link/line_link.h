// The HIL link on a byte stream: LinkMessages framed by dut_link/line_framing.h (COBS over the
// message and its CRC-16, ended by a zero byte), as a serial line to a board or an emulated MCU
// carries them. A frame that fails its CRC, is not valid COBS, is too long, or does not parse as
// a LinkMessage is counted and skipped: the decoder is back in step at the next zero byte, so a
// lost or flipped byte costs one message, never the link.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "dut_link/line_framing.h"
#include "host/link/byte_stream.h"
#include "proto/hil_link.pb.h"
#include "rig/metric.h"
#include "rig/result.h"

namespace hilrig::host {

struct LineLinkCounters {
  std::uint64_t frames_sent = 0;
  std::uint64_t bytes_sent = 0;
  std::uint64_t frames_received = 0;  // frames that parsed as a LinkMessage
  std::uint64_t bytes_received = 0;
  std::uint64_t bad_checksum = 0;
  std::uint64_t malformed = 0;  // bad COBS, too short, or a payload that is no LinkMessage
  std::uint64_t oversize = 0;
};

// Named report metrics ("<prefix>frames_sent", ...), for DutPort::link_metrics.
std::vector<rig::Metric> LineLinkMetrics(const LineLinkCounters& counters,
                                         const std::string& prefix);

enum class LineReceiveStatus {
  kMessage,  // `message` holds the next message
  kTimeout,  // no complete message before the deadline
  kClosed,   // the peer hung up, and no complete message was left
  kError,    // the stream failed; `error` says why
};

struct LineReceived {
  LineReceiveStatus status = LineReceiveStatus::kTimeout;
  proto::LinkMessage message;
  std::string error;
};

class LineLink {
 public:
  // `stream` must outlive the link.
  explicit LineLink(ByteStream& stream);

  // Frames and writes `message`. `flush_first` leads with a zero byte, which ends whatever frame
  // the receiver had half assembled (worth a byte when opening a session or repeating a frame).
  rig::Result<void> Send(const proto::LinkMessage& message, int timeout_ms,
                         bool flush_first = false);
  // The next message, waiting at most timeout_ms (0: only what has arrived).
  LineReceived Receive(int timeout_ms);

  const LineLinkCounters& counters() const;
  ByteStream& stream() { return stream_; }

 private:
  // The next message in the bytes read but not yet decoded; bad frames are counted and skipped.
  bool TakeBuffered(proto::LinkMessage& message);

  ByteStream& stream_;
  dut_link::FrameDecoder<dut_link::kMaxLineMessageBytes> decoder_;
  std::array<std::uint8_t, 1024> chunk_{};
  std::size_t chunk_size_ = 0;
  std::size_t chunk_at_ = 0;
  std::vector<std::uint8_t> encoded_;
  mutable LineLinkCounters counters_;
  std::uint64_t unparsed_ = 0;  // CRC-valid frames that did not parse: counted as malformed
};

}  // namespace hilrig::host
