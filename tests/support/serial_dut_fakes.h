// Fakes of the platform interfaces dut_link/serial_session.h runs on, for tests: a sink that
// keeps what the session wrote and hands it back as parsed LinkMessages, a bridge line fed from a
// queue, a clock and a cycle counter that advance by a fixed step on every read (so a wait on the
// bridge ends after a known number of reads, with no wall time), and the runner's side of the
// line: LinkMessages framed as the session expects them.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dut_link/line_framing.h"
#include "dut_link/serial_session.h"
#include "proto/hil_link.pb.h"

namespace hilrig::dut_fw {

class RecordingSink final : public dut_link::LineSink {
 public:
  void Write(std::span<const std::uint8_t> bytes) override {
    for (const std::uint8_t byte : bytes) {
      ++bytes_written;
      if (const auto payload = decoder_.Feed(byte)) {
        proto::LinkMessage message;
        EXPECT_TRUE(message.ParseFromArray(payload->data(), int(payload->size())));
        messages_.push_back(message);
        payload_sizes.push_back(payload->size());
      }
    }
  }

  // The messages written since the last call.
  std::vector<proto::LinkMessage> Take() {
    std::vector<proto::LinkMessage> taken;
    taken.swap(messages_);
    return taken;
  }

  std::size_t bytes_written = 0;
  std::vector<std::size_t> payload_sizes;  // every frame's message size, in order

 private:
  dut_link::FrameDecoder<dut_link::kMaxLineMessageBytes> decoder_;
  std::vector<proto::LinkMessage> messages_;
};

class QueueByteSource final : public dut_link::ByteSource {
 public:
  std::optional<std::uint8_t> ReadByte() override {
    if (bytes.empty()) return std::nullopt;
    const std::uint8_t byte = bytes.front();
    bytes.pop_front();
    return byte;
  }
  std::deque<std::uint8_t> bytes;
};

class SteppingClock final : public dut_link::MonotonicClock {
 public:
  std::int64_t NowNs() override {
    ++reads;
    return now_ns += step_ns;
  }
  std::int64_t now_ns = 0;
  std::int64_t step_ns = 1'000'000;
  int reads = 0;
};

class SteppingCycleCounter final : public dut_link::CycleCounter {
 public:
  std::uint32_t Cycles() override { return cycles += step; }
  std::uint32_t cycles = 0;
  std::uint32_t step = 0;  // 0: work reads as 0
};

// The line form of `message`, as the runner writes it.
inline std::vector<std::uint8_t> LineFrame(const proto::LinkMessage& message) {
  const std::string payload = message.SerializeAsString();
  std::vector<std::uint8_t> line(dut_link::EncodedFrameBytes(payload.size()));
  line.resize(dut_link::EncodeFrame(
      std::span(reinterpret_cast<const std::uint8_t*>(payload.data()), payload.size()), line));
  return line;
}

}  // namespace hilrig::dut_fw
