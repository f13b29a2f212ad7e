// Reads an MCAP file (https://mcap.dev/spec) as McapWriter writes it, or any file of the same
// records: the Header, the Schema and Channel records, every Message (in chunks, zstd or stored,
// or outside them) in file order, and the summary's Statistics. It checks the magic at both ends,
// each record's length against the bytes left, the data section's CRC-32 (DataEnd), the summary's
// (Footer) and each chunk's uncompressed CRC-32; unknown opcodes are skipped, as the format asks.
// Malformed input is a McapError with its kind and the byte offset of the record at fault, never a
// crash; decompressed sizes are held to the chunk's stated size and to McapReadLimits.
// RecoverMcap reads a file whose writer was killed: the records up to the first incomplete one.
// Complexity: O(file + decompressed bytes); memory: the messages' payloads plus one chunk.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hilrig::mcap {

enum class McapErrorKind {
  kBadMagic,            // the file does not start, or end, with the MCAP magic
  kTruncated,           // a record runs past the end of the file
  kMalformedRecord,     // a field runs past its record's end, or a record is out of place
  kBadFooter,           // the Footer's offsets point outside the file
  kDataCrcMismatch,     // DataEnd's CRC-32 is not that of the data section
  kSummaryCrcMismatch,  // the Footer's CRC-32 is not that of the summary
  kChunkCrcMismatch,    // a chunk's records do not have its stated CRC-32
  kUnknownCompression,  // a chunk compressed other than with zstd or not at all
  kBadCompressedData,   // zstd refused a chunk, or it did not give the stated size
  kTooLarge,            // a size past McapReadLimits
  kUnknownChannel,      // a message on a channel no Channel record defined
  kUnknownSchema,       // a channel of a schema no Schema record defined
  kMissingDataEnd,      // the records end before DataEnd
  kUnreadableFile,      // the file could not be opened or read
};

struct McapError {
  McapErrorKind kind;
  std::uint64_t offset = 0;  // of the record at fault, from the start of the file
  std::string detail;        // for people
};

struct McapReadLimits {
  std::uint64_t max_chunk_uncompressed_bytes = 256ull << 20;
  // All chunks together: a file of many small, highly compressed chunks stays bounded too.
  std::uint64_t max_total_uncompressed_bytes = 2ull << 30;
  std::uint64_t max_file_bytes = 2ull << 30;  // ReadMcapFile
};

struct McapSchema {
  std::uint16_t id = 0;
  std::string name;
  std::string encoding;
  std::string data;
};

struct McapChannel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;
  std::map<std::string, std::string> metadata;
};

struct McapMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::string payload;
};

struct McapStatistics {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0;
  std::uint32_t chunk_count = 0;
  std::uint64_t message_start_ns = 0;
  std::uint64_t message_end_ns = 0;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

struct McapContents {
  std::string profile;
  std::string library;
  std::map<std::uint16_t, McapSchema> schemas;
  std::map<std::uint16_t, McapChannel> channels;
  std::vector<McapMessage> messages;         // in file order: chunk by chunk
  std::uint32_t chunk_count = 0;             // chunks read
  std::optional<McapStatistics> statistics;  // from the summary, when it has one
  std::uint32_t chunk_index_count = 0;       // ChunkIndex records in the summary
  // RecoverMcap only: the file ended before its Footer, and the bytes read up to the first
  // incomplete record.
  bool truncated = false;
  std::uint64_t complete_bytes = 0;
};

struct McapReadResult {
  std::optional<McapError> error;  // when set, `contents` is not to be trusted
  McapContents contents;
  bool ok() const { return !error.has_value(); }
};

// The whole file, every check made. Fails with a McapError on any malformed input; allocates the
// contents (a copy of every payload) and one chunk's records, each held to `limits`.
McapReadResult ReadMcap(std::string_view bytes, const McapReadLimits& limits = {});
// A file that may have been cut short: a complete file reads as ReadMcap reads it; otherwise the
// records from the start up to the first incomplete one (a chunk cut in two is dropped whole),
// flagged `truncated`. A complete record that is malformed is still an error. Allocates as
// ReadMcap does.
McapReadResult RecoverMcap(std::string_view bytes, const McapReadLimits& limits = {});
// ReadMcap (or RecoverMcap, with `recover`) of a file no larger than limits.max_file_bytes: fails
// (kUnreadableFile, kTooLarge) before reading otherwise; allocates the file's bytes.
McapReadResult ReadMcapFile(const std::filesystem::path& path, bool recover = false,
                            const McapReadLimits& limits = {});

}  // namespace hilrig::mcap
