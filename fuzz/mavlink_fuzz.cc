// Fuzz target for the MAVLink v2 stream parser and message codec (host/mavlink): the input is a
// raw byte stream as a serial port or UDP socket would deliver it, and also read as a telemetry
// log. Properties checked beyond "does not crash": the frames and counters do not depend on how
// the stream is chunked; every delivered frame is of a known message, within its length, zero
// past its payload, and re-encodes to a frame that parses back equal; every payload decodes to a
// message that packs back to the same bytes; and the counted events never outnumber the bytes
// seen. Corpus: fuzz/corpus/mavlink.
#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "fuzz/fuzz_target.h"
#include "host/mavlink/mavlink_frame.h"
#include "host/mavlink/mavlink_messages.h"
#include "host/mavlink/tlog.h"

namespace {

using namespace hilrig::mavlink;

void Require(bool condition) {
  if (!condition) __builtin_trap();
}

struct Run {
  std::vector<Frame> frames;
  ParserCounters counters;
};

Run ParseInChunks(std::span<const std::uint8_t> data, std::size_t chunk) {
  FrameParser parser(&FindWireInfo);
  Run run;
  const auto keep = [&](const Frame& frame) { run.frames.push_back(frame); };
  for (std::size_t at = 0; at < data.size(); at += chunk) {
    parser.Feed(data.subspan(at, std::min(chunk, data.size() - at)), keep);
  }
  parser.Finish();
  while (std::optional<Frame> frame = parser.Next()) keep(*frame);
  run.counters = parser.counters();
  return run;
}

std::uint64_t CountedEvents(const ParserCounters& c) {
  return c.frames_ok + c.bytes_skipped + c.crc_failures + c.unknown_message_ids + c.bad_lengths +
         c.unsupported_incompat_flags + c.v1_frames_skipped + c.truncated_frames;
}

void CheckReencodes(const Frame& frame) {
  const MessageInfo* info = FindMessage(frame.message_id);
  Require(info != nullptr);
  Require(frame.payload_length <= info->full_payload_bytes);
  Require(std::all_of(frame.payload.begin() + frame.payload_length, frame.payload.end(),
                      [](std::uint8_t b) { return b == 0; }));

  // The encoder neither signs nor keeps trailing zeros.
  Frame expected = frame;
  expected.incompat_flags = 0;
  expected.payload_length = static_cast<std::uint8_t>(TrimmedPayloadLength(
      std::span<const std::uint8_t>(frame.payload.data(), frame.payload_length)));
  std::array<std::uint8_t, kMaxFrameBytes> bytes{};
  const std::size_t size = EncodeFrame(expected, info->crc_extra, bytes);
  Require(size == kHeaderBytes + expected.payload_length + kChecksumBytes);
  FrameParser parser(&FindWireInfo);
  std::optional<Frame> again;
  for (std::size_t i = 0; i < size; ++i) {
    parser.Push(std::span<const std::uint8_t>(&bytes[i], 1));
    if (std::optional<Frame> frame_out = parser.Next()) {
      Require(!again.has_value());
      again = frame_out;
    }
  }
  Require(again.has_value() && *again == expected);
  Require(parser.counters() == ParserCounters{.frames_ok = 1});

  const std::optional<AnyMessage> message = DecodeMessage(frame);
  Require(message.has_value() && MessageId(*message) == frame.message_id);
  std::visit(
      [&](const auto& m) {
        using M = std::remove_cvref_t<decltype(m)>;
        std::array<std::uint8_t, M::kFullPayloadBytes> packed{};
        Pack(m, std::span(packed));
        Require(std::equal(packed.begin(), packed.end(), frame.payload.begin()));
      },
      *message);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> input(data, size);
  const Run whole = ParseInChunks(input, std::max<std::size_t>(size, 1));
  Require(whole.counters.frames_ok == whole.frames.size());
  Require(whole.counters.signed_frames <= whole.counters.frames_ok);
  Require(CountedEvents(whole.counters) <= size);
  for (const Frame& frame : whole.frames) CheckReencodes(frame);

  const std::size_t odd_chunk = size == 0 ? 1 : 1 + data[0] % 29;
  for (const std::size_t chunk : {std::size_t{1}, odd_chunk}) {
    const Run chunked = ParseInChunks(input, chunk);
    Require(chunked.frames == whole.frames);
    Require(chunked.counters == whole.counters);
  }

  const TlogContents log = ReadTlog(input);
  Require(log.bytes_skipped <= size);
  for (const TlogRecord& record : log.records) CheckReencodes(record.frame);
  return 0;
}
