#include "dut_link/line_framing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace hilrig::dut_link {
namespace {

constexpr std::size_t kMaxPayload = 600;
using Decoder = FrameDecoder<kMaxPayload>;

std::vector<std::uint8_t> Encode(const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> line(EncodedFrameBytes(payload.size()));
  line.resize(EncodeFrame(payload, line));
  return line;
}

// Every payload the decoder delivers for `line`, fed byte by byte.
std::vector<std::vector<std::uint8_t>> DecodeAll(Decoder& decoder,
                                                 const std::vector<std::uint8_t>& line) {
  std::vector<std::vector<std::uint8_t>> payloads;
  for (const std::uint8_t byte : line) {
    if (const auto payload = decoder.Feed(byte))
      payloads.emplace_back(payload->begin(), payload->end());
  }
  return payloads;
}

std::vector<std::uint8_t> Pattern(std::size_t size, std::uint8_t seed) {
  std::vector<std::uint8_t> bytes(size);
  for (std::size_t i = 0; i < size; ++i)
    bytes[i] = std::uint8_t((i * 37 + seed) % 7 == 0 ? 0 : i + seed);
  return bytes;
}

std::vector<std::uint8_t> Concat(std::initializer_list<std::vector<std::uint8_t>> parts) {
  std::vector<std::uint8_t> all;
  for (const auto& part : parts) all.insert(all.end(), part.begin(), part.end());
  return all;
}

TEST(LineFraming, CrcIsCcittFalse) {
  const std::vector<std::uint8_t> check = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(Crc16CcittFalse(check), 0x29B1);  // the catalogue's check value
}

TEST(LineFraming, RoundTripsPayloadsOfEverySizeWithZerosAndRuns) {
  for (std::size_t size : {0u, 1u, 2u, 252u, 253u, 254u, 255u, 507u, 508u, 600u}) {
    for (const auto& payload : {Pattern(size, 3), std::vector<std::uint8_t>(size, 0),
                                std::vector<std::uint8_t>(size, 0xFF)}) {
      const std::vector<std::uint8_t> line = Encode(payload);
      ASSERT_LE(line.size(), EncodedFrameBytes(size)) << "size " << size;
      EXPECT_EQ(std::count(line.begin(), line.end() - 1, 0), 0) << "size " << size;
      EXPECT_EQ(line.back(), kFrameDelimiter);
      Decoder decoder;
      const auto payloads = DecodeAll(decoder, line);
      ASSERT_EQ(payloads.size(), 1u) << "size " << size;
      EXPECT_EQ(payloads[0], payload) << "size " << size;
    }
  }
}

TEST(LineFraming, RefusesAnOutputBufferTooSmall) {
  const std::vector<std::uint8_t> payload = Pattern(10, 1);
  std::vector<std::uint8_t> out(EncodedFrameBytes(payload.size()) - 1);
  EXPECT_EQ(EncodeFrame(payload, out), 0u);
}

TEST(LineFraming, CountsAndDropsAFlippedByteThenResynchronises) {
  const std::vector<std::uint8_t> first = Pattern(40, 1), second = Pattern(40, 2);
  std::vector<std::uint8_t> damaged = Encode(first);
  damaged[10] ^= 0x04;
  Decoder decoder;
  const auto payloads = DecodeAll(decoder, Concat({damaged, Encode(second)}));
  ASSERT_EQ(payloads.size(), 1u);
  EXPECT_EQ(payloads[0], second);
  EXPECT_EQ(decoder.counters().bad_checksums + decoder.counters().malformed, 1u);
  EXPECT_EQ(decoder.counters().frames, 1u);
}

TEST(LineFraming, LosesOnlyTheFrameALostByteWasIn) {
  const std::vector<std::uint8_t> first = Pattern(40, 1), second = Pattern(40, 2);
  for (std::size_t lost = 0; lost + 1 < Encode(first).size(); ++lost) {
    std::vector<std::uint8_t> damaged = Encode(first);
    damaged.erase(damaged.begin() + std::ptrdiff_t(lost));
    Decoder decoder;
    const auto payloads = DecodeAll(decoder, Concat({damaged, Encode(second)}));
    ASSERT_EQ(payloads.size(), 1u) << "lost byte " << lost;
    EXPECT_EQ(payloads[0], second);
    EXPECT_EQ(decoder.counters().bad_checksums + decoder.counters().malformed, 1u);
  }
}

TEST(LineFraming, LosesOnlyTheFrameAnInsertedDelimiterSplit) {
  const std::vector<std::uint8_t> first = Pattern(40, 1), second = Pattern(40, 2);
  std::vector<std::uint8_t> damaged = Encode(first);
  damaged.insert(damaged.begin() + 20, kFrameDelimiter);
  Decoder decoder;
  const auto payloads = DecodeAll(decoder, Concat({damaged, Encode(second)}));
  ASSERT_EQ(payloads.size(), 1u);
  EXPECT_EQ(payloads[0], second);
  EXPECT_EQ(decoder.counters().bad_checksums + decoder.counters().malformed, 2u);
}

TEST(LineFraming, SkipsLeadingGarbageAndIdleDelimiters) {
  const std::vector<std::uint8_t> payload = Pattern(30, 5);
  const std::vector<std::uint8_t> garbage = {0x13, 0x37, 0xFF, 0x02, 0x00, 0x00, 0x00};
  Decoder decoder;
  const auto payloads = DecodeAll(decoder, Concat({garbage, Encode(payload)}));
  ASSERT_EQ(payloads.size(), 1u);
  EXPECT_EQ(payloads[0], payload);
  EXPECT_EQ(decoder.counters().frames, 1u);
  EXPECT_EQ(decoder.counters().bad_checksums + decoder.counters().malformed, 1u);
}

TEST(LineFraming, SkipsAnOversizeFrameToItsDelimiter) {
  const std::vector<std::uint8_t> big = Pattern(kMaxPayload + 50, 1), small = Pattern(20, 2);
  Decoder decoder;
  const auto payloads = DecodeAll(decoder, Concat({Encode(big), Encode(small)}));
  ASSERT_EQ(payloads.size(), 1u);
  EXPECT_EQ(payloads[0], small);
  EXPECT_EQ(decoder.counters().oversize, 1u);
}

}  // namespace
}  // namespace hilrig::dut_link
