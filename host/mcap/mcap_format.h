// The MCAP container's fixed facts (https://mcap.dev/spec) that the writer and the reader share:
// the magic, the record opcodes and the little-endian encodings of its field types. A record is
// <opcode u8><content length u64><content>; a String is <u32 length><bytes>; a Map or an Array is
// <u32 byte length><entries>. Appending never fails; it grows the string it appends to.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace hilrig::mcap {

// 0x89 "MCAP" '0' (major version 0) "\r\n": at the start and at the end of every file.
inline constexpr std::string_view kMagic("\x89MCAP0\r\n", 8);
inline constexpr std::uint64_t kRecordPrefixBytes = 1 + 8;
// Footer content: summary_start u64, summary_offset_start u64, summary_crc u32.
inline constexpr std::uint64_t kFooterContentBytes = 8 + 8 + 4;
inline constexpr std::uint64_t kFooterRecordBytes = kRecordPrefixBytes + kFooterContentBytes;

enum class Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// Message content before the payload: channel_id u16, sequence u32, log_time u64,
// publish_time u64.
inline constexpr std::uint64_t kMessageFixedBytes = 2 + 4 + 8 + 8;

// Stores `value` at `at` least significant byte first (the compiler makes one store of it).
template <typename T>
void PutLittleEndian(char* at, T value) {
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    at[i] = static_cast<char>(static_cast<std::uint64_t>(value) >> (8 * i) & 0xFFu);
  }
}

template <typename T>
void AppendLittleEndian(std::string& out, T value) {
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    out.push_back(static_cast<char>(static_cast<std::uint64_t>(value) >> (8 * i) & 0xFFu));
  }
}

inline void AppendString(std::string& out, std::string_view text) {
  AppendLittleEndian<std::uint32_t>(out, static_cast<std::uint32_t>(text.size()));
  out.append(text);
}

// <opcode><content length> for a record whose content follows.
inline void AppendRecordPrefix(std::string& out, Opcode opcode, std::uint64_t content_bytes) {
  out.push_back(static_cast<char>(opcode));
  AppendLittleEndian<std::uint64_t>(out, content_bytes);
}

inline void AppendRecord(std::string& out, Opcode opcode, std::string_view content) {
  AppendRecordPrefix(out, opcode, content.size());
  out.append(content);
}

}  // namespace hilrig::mcap
