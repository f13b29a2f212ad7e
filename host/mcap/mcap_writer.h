// McapWriter streams an MCAP file (https://mcap.dev/spec) to a std::ostream: the leading magic and
// Header; each Schema and Channel record in the data section when it is added; Message records
// gathered into Chunk records, zstd-compressed (or stored as they are), each followed by one
// MessageIndex record per channel it holds; then, at Close(), DataEnd with the CRC-32 of every byte
// before it, the summary section (every Schema and Channel again, one Statistics record, one
// ChunkIndex per chunk), one SummaryOffset per summary group, the Footer (with the CRC-32 of the
// summary through the Footer's summary_offset_start) and the closing magic.
// Complexity: Write() is O(payload) amortised; a chunk is compressed once when its uncompressed
// records pass `chunk_bytes`, on the caller's thread or (McapWriterOptions::background) on the
// writer's own. Memory: one chunk's records and its compressed copy (and one chunk in flight in the
// background), the current chunk's message index (16 bytes a message) and one ChunkIndex a chunk;
// it does not grow with the number of messages otherwise.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "rig/result.h"

namespace hilrig::mcap {

enum class ChunkCompression { kZstd, kNone };

struct McapWriterOptions {
  ChunkCompression compression = ChunkCompression::kZstd;
  // A chunk is closed once its uncompressed records reach this size.
  std::size_t chunk_bytes = 1 << 20;
  int zstd_level = 1;  // fast: a run's log is written while the run goes on
  // Compress, checksum and write each full chunk on a thread of the writer's own while the caller
  // fills the next one (one chunk in flight; the caller waits only when the next is full first).
  // Failures come back from the next Write, AddSchema, AddChannel or Close.
  bool background = false;
};

struct MessageToWrite {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::string_view payload;
};

class McapWriter {
 public:
  explicit McapWriter(std::ostream& out, McapWriterOptions options = {});
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Writes the magic and the Header. Fails (kIo) when the stream does; allocates the record.
  rig::Result<void> Open(std::string_view profile, std::string_view library);
  // Writes a Schema record; returns its id (1, 2, ...). Fails when the stream does or after 65535
  // schemas; allocates its copy for the summary.
  rig::Result<std::uint16_t> AddSchema(std::string_view name, std::string_view encoding,
                                       std::string_view data);
  // Writes a Channel record; returns its id (0, 1, ...). Fails when the stream does, when
  // `schema_id` is neither 0 (no schema) nor an added schema, or after 65536 channels; allocates
  // its copy for the summary.
  rig::Result<std::uint16_t> AddChannel(std::uint16_t schema_id, std::string_view topic,
                                        std::string_view message_encoding,
                                        const std::map<std::string, std::string>& metadata = {});
  // Appends a Message to the current chunk, writing the chunk when it is full. Fails on an unknown
  // channel, before Open() or after Close(), and when the stream or the compressor does. Allocates
  // only while the chunk buffers grow to their first full chunk, and per-chunk index entries.
  rig::Result<void> Write(const MessageToWrite& message);
  // Writes the last chunk, DataEnd, the summary, the Footer and the magic, and flushes. Fails when
  // the stream or the compressor does; a second call does nothing.
  rig::Result<void> Close();

 private:
  struct ChunkIndexEntry {
    std::uint64_t start_ns = 0;
    std::uint64_t end_ns = 0;
    std::uint64_t chunk_offset = 0;
    std::uint64_t chunk_record_bytes = 0;
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;  // channel -> file offset
    std::uint64_t message_index_bytes = 0;
    std::uint64_t compressed_bytes = 0;
    std::uint64_t uncompressed_bytes = 0;
  };

  // Per channel id, the chunk's (log time, offset) pairs; empty for a channel without messages.
  using ChunkMessageIndex = std::vector<std::string>;

  rig::Result<void> Emit(std::string_view bytes);
  rig::Result<void> FlushChunk();
  // Compresses and writes one chunk and its message indexes; the worker's job in the background.
  rig::Result<void> WriteChunk(const std::string& records, const ChunkMessageIndex& index,
                               std::uint64_t start_ns, std::uint64_t end_ns);
  rig::Result<void> WriteMessageIndexes(const ChunkMessageIndex& index, ChunkIndexEntry& entry);
  // Waits for the chunk in flight; its failure, or the worker's first, if any.
  rig::Result<void> Settle();
  void WorkerLoop();
  void StopWorker();
  std::string StatisticsContent() const;
  std::string ChunkIndexRecord(const ChunkIndexEntry& entry) const;
  rig::Result<void> WriteSummaryAndFooter();

  std::ostream& out_;
  McapWriterOptions options_;
  void* zstd_context_ = nullptr;  // ZSTD_CCtx, reused for every chunk
  bool open_ = false;
  bool closed_ = false;
  std::uint64_t offset_ = 0;       // bytes written so far: the next record's file offset
  std::uint32_t running_crc_ = 0;  // of the data section, then of the summary section

  std::vector<std::string> schema_records_;   // whole records, repeated in the summary
  std::vector<std::string> channel_records_;  // likewise

  // The open chunk: its records, their times, and per channel (log time, offset) pairs.
  std::string chunk_records_;
  std::string compressed_;
  std::uint64_t chunk_start_ns_ = 0;
  std::uint64_t chunk_end_ns_ = 0;
  ChunkMessageIndex chunk_message_index_;

  // The file's totals and one index entry per written chunk.
  std::uint64_t message_count_ = 0;
  std::uint64_t message_start_ns_ = 0;
  std::uint64_t message_end_ns_ = 0;
  std::vector<std::uint64_t> channel_message_counts_;  // by channel id
  std::vector<ChunkIndexEntry> chunk_indexes_;

  // The background worker and the chunk in flight (options_.background). The worker alone touches
  // the stream, offset_, running_crc_, chunk_indexes_ and the compressor while a job is pending.
  std::thread worker_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool job_pending_ = false;
  bool stopping_ = false;
  std::optional<rig::Error> worker_failure_;
  std::string job_records_;
  ChunkMessageIndex job_index_;
  std::uint64_t job_start_ns_ = 0;
  std::uint64_t job_end_ns_ = 0;
};

}  // namespace hilrig::mcap
