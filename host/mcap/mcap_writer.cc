#include "host/mcap/mcap_writer.h"

#include <zstd.h>

#include <algorithm>
#include <limits>
#include <utility>

#include "host/mcap/crc32.h"
#include "host/mcap/mcap_format.h"

namespace hilrig::mcap {
namespace {

std::string_view CompressionName(ChunkCompression compression) {
  return compression == ChunkCompression::kZstd ? "zstd" : "";
}

std::string SchemaRecord(std::uint16_t id, std::string_view name, std::string_view encoding,
                         std::string_view data) {
  std::string content;
  AppendLittleEndian<std::uint16_t>(content, id);
  AppendString(content, name);
  AppendString(content, encoding);
  AppendString(content, data);  // uint32 length-prefixed bytes: the same layout as a String
  std::string record;
  AppendRecord(record, Opcode::kSchema, content);
  return record;
}

std::string ChannelRecord(std::uint16_t id, std::uint16_t schema_id, std::string_view topic,
                          std::string_view message_encoding,
                          const std::map<std::string, std::string>& metadata) {
  std::string entries;
  for (const auto& [key, value] : metadata) {
    AppendString(entries, key);
    AppendString(entries, value);
  }
  std::string content;
  AppendLittleEndian<std::uint16_t>(content, id);
  AppendLittleEndian<std::uint16_t>(content, schema_id);
  AppendString(content, topic);
  AppendString(content, message_encoding);
  AppendString(content, entries);  // a Map: u32 byte length, then the entries
  std::string record;
  AppendRecord(record, Opcode::kChannel, content);
  return record;
}

rig::Error WriterError(std::string message) {
  return rig::MakeError("mcap writer: " + std::move(message));
}

}  // namespace

McapWriter::McapWriter(std::ostream& out, McapWriterOptions options)
    : out_(out), options_(options) {}

McapWriter::~McapWriter() {
  StopWorker();
  ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(zstd_context_));
}

rig::Result<void> McapWriter::Settle() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [this] { return !job_pending_; });
  if (worker_failure_) return *worker_failure_;
  return {};
}

void McapWriter::WorkerLoop() {
  std::unique_lock lock(mutex_);
  while (true) {
    changed_.wait(lock, [this] { return job_pending_ || stopping_; });
    if (!job_pending_) return;  // stopping, nothing in flight
    lock.unlock();
    rig::Result<void> written = WriteChunk(job_records_, job_index_, job_start_ns_, job_end_ns_);
    lock.lock();
    if (!written && !worker_failure_) worker_failure_ = written.error();
    job_pending_ = false;
    changed_.notify_all();
  }
}

void McapWriter::StopWorker() {
  if (!worker_.joinable()) return;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

rig::Result<void> McapWriter::Emit(std::string_view bytes) {
  out_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out_) return rig::MakeError(rig::ErrorCode::kIo, "mcap writer: the stream refused a write");
  offset_ += bytes.size();
  running_crc_ = Crc32Update(running_crc_, bytes);
  return {};
}

rig::Result<void> McapWriter::Open(std::string_view profile, std::string_view library) {
  if (open_ || closed_) return WriterError("Open() called twice");
  std::string content;
  AppendString(content, profile);
  AppendString(content, library);
  std::string bytes(kMagic);
  AppendRecord(bytes, Opcode::kHeader, content);
  open_ = true;
  return Emit(bytes);
}

rig::Result<std::uint16_t> McapWriter::AddSchema(std::string_view name, std::string_view encoding,
                                                 std::string_view data) {
  if (!open_ || closed_) return WriterError("AddSchema() outside Open() and Close()");
  if (auto settled = Settle(); !settled) return settled.error();
  if (schema_records_.size() >= std::numeric_limits<std::uint16_t>::max()) {
    return WriterError("more than 65535 schemas");
  }
  const auto id = static_cast<std::uint16_t>(schema_records_.size() + 1);  // 0 means "none"
  schema_records_.push_back(SchemaRecord(id, name, encoding, data));
  if (auto written = Emit(schema_records_.back()); !written) return written.error();
  return id;
}

rig::Result<std::uint16_t> McapWriter::AddChannel(
    std::uint16_t schema_id, std::string_view topic, std::string_view message_encoding,
    const std::map<std::string, std::string>& metadata) {
  if (!open_ || closed_) return WriterError("AddChannel() outside Open() and Close()");
  if (auto settled = Settle(); !settled) return settled.error();
  if (schema_id > schema_records_.size()) {
    return WriterError("channel " + std::string(topic) + " names an unknown schema");
  }
  if (channel_records_.size() > std::numeric_limits<std::uint16_t>::max()) {
    return WriterError("more than 65536 channels");
  }
  const auto id = static_cast<std::uint16_t>(channel_records_.size());
  channel_records_.push_back(ChannelRecord(id, schema_id, topic, message_encoding, metadata));
  chunk_message_index_.resize(channel_records_.size());
  channel_message_counts_.resize(channel_records_.size());
  if (auto written = Emit(channel_records_.back()); !written) return written.error();
  return id;
}

rig::Result<void> McapWriter::Write(const MessageToWrite& message) {
  if (!open_ || closed_) return WriterError("Write() outside Open() and Close()");
  if (message.channel_id >= channel_records_.size()) {
    return WriterError("a message on unknown channel " + std::to_string(message.channel_id));
  }
  // The record's fixed part and the index entry are put together on the stack and appended
  // whole: a run's log writes a hundred thousand small messages.
  const std::uint64_t offset_in_chunk = chunk_records_.size();
  char head[kRecordPrefixBytes + kMessageFixedBytes];
  head[0] = static_cast<char>(Opcode::kMessage);
  PutLittleEndian<std::uint64_t>(head + 1, kMessageFixedBytes + message.payload.size());
  PutLittleEndian<std::uint16_t>(head + 9, message.channel_id);
  PutLittleEndian<std::uint32_t>(head + 11, message.sequence);
  PutLittleEndian<std::uint64_t>(head + 15, message.log_time_ns);
  PutLittleEndian<std::uint64_t>(head + 23, message.publish_time_ns);
  chunk_records_.append(head, sizeof(head));
  chunk_records_.append(message.payload);

  char entry[16];
  PutLittleEndian<std::uint64_t>(entry, message.log_time_ns);
  PutLittleEndian<std::uint64_t>(entry + 8, offset_in_chunk);
  chunk_message_index_[message.channel_id].append(entry, sizeof(entry));  // sized at AddChannel

  const bool first_in_chunk = offset_in_chunk == 0;
  chunk_start_ns_ =
      first_in_chunk ? message.log_time_ns : std::min(chunk_start_ns_, message.log_time_ns);
  chunk_end_ns_ =
      first_in_chunk ? message.log_time_ns : std::max(chunk_end_ns_, message.log_time_ns);
  const bool first_in_file = message_count_ == 0;
  message_start_ns_ =
      first_in_file ? message.log_time_ns : std::min(message_start_ns_, message.log_time_ns);
  message_end_ns_ =
      first_in_file ? message.log_time_ns : std::max(message_end_ns_, message.log_time_ns);
  ++message_count_;
  ++channel_message_counts_[message.channel_id];

  if (chunk_records_.size() >= options_.chunk_bytes) return FlushChunk();
  return {};
}

rig::Result<void> McapWriter::FlushChunk() {
  if (chunk_records_.empty()) return {};
  if (!options_.background) {
    rig::Result<void> written =
        WriteChunk(chunk_records_, chunk_message_index_, chunk_start_ns_, chunk_end_ns_);
    chunk_records_.clear();  // keeps its capacity: the next chunk allocates nothing
    for (std::string& packed : chunk_message_index_) packed.clear();
    return written;
  }
  if (auto settled = Settle(); !settled) return settled;
  // The worker is idle: the chunk becomes its job, and its previous job's buffers this chunk's.
  std::swap(chunk_records_, job_records_);
  std::swap(chunk_message_index_, job_index_);
  job_start_ns_ = chunk_start_ns_;
  job_end_ns_ = chunk_end_ns_;
  chunk_records_.clear();
  chunk_message_index_.resize(channel_records_.size());
  for (std::string& packed : chunk_message_index_) packed.clear();
  {
    std::lock_guard lock(mutex_);
    job_pending_ = true;
  }
  if (!worker_.joinable()) worker_ = std::thread([this] { WorkerLoop(); });
  changed_.notify_all();
  return {};
}

rig::Result<void> McapWriter::WriteChunk(const std::string& records, const ChunkMessageIndex& index,
                                         std::uint64_t start_ns, std::uint64_t end_ns) {
  std::string_view stored = records;
  if (options_.compression == ChunkCompression::kZstd) {
    if (zstd_context_ == nullptr) zstd_context_ = ZSTD_createCCtx();
    if (zstd_context_ == nullptr) return WriterError("zstd could not make its context");
    compressed_.resize(ZSTD_compressBound(records.size()));
    const std::size_t size =
        ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(zstd_context_), compressed_.data(),
                          compressed_.size(), records.data(), records.size(), options_.zstd_level);
    if (ZSTD_isError(size) != 0) {
      return WriterError(std::string("zstd refused a chunk: ") + ZSTD_getErrorName(size));
    }
    stored = std::string_view(compressed_.data(), size);
  }
  const std::string_view compression = CompressionName(options_.compression);
  const std::uint64_t content_bytes = 8 + 8 + 8 + 4 + 4 + compression.size() + 8 + stored.size();
  std::string head;
  AppendRecordPrefix(head, Opcode::kChunk, content_bytes);
  AppendLittleEndian<std::uint64_t>(head, start_ns);
  AppendLittleEndian<std::uint64_t>(head, end_ns);
  AppendLittleEndian<std::uint64_t>(head, records.size());
  AppendLittleEndian<std::uint32_t>(head, Crc32(records));
  AppendString(head, compression);
  AppendLittleEndian<std::uint64_t>(head, stored.size());

  ChunkIndexEntry entry{.start_ns = start_ns,
                        .end_ns = end_ns,
                        .chunk_offset = offset_,
                        .chunk_record_bytes = kRecordPrefixBytes + content_bytes,
                        .message_index_offsets = {},
                        .message_index_bytes = 0,
                        .compressed_bytes = stored.size(),
                        .uncompressed_bytes = records.size()};
  if (auto written = Emit(head); !written) return written;
  if (auto written = Emit(stored); !written) return written;
  if (auto written = WriteMessageIndexes(index, entry); !written) return written;
  chunk_indexes_.push_back(std::move(entry));
  return {};
}

rig::Result<void> McapWriter::WriteMessageIndexes(const ChunkMessageIndex& index,
                                                  ChunkIndexEntry& entry) {
  const std::uint64_t start = offset_;
  std::string record;
  for (std::size_t channel_id = 0; channel_id < index.size(); ++channel_id) {
    const std::string& packed = index[channel_id];
    if (packed.empty()) continue;
    record.clear();
    AppendRecordPrefix(record, Opcode::kMessageIndex, 2 + 4 + packed.size());
    AppendLittleEndian<std::uint16_t>(record, static_cast<std::uint16_t>(channel_id));
    AppendString(record, packed);  // an Array: u32 byte length, then (log_time, offset) pairs
    entry.message_index_offsets[static_cast<std::uint16_t>(channel_id)] = offset_;
    if (auto written = Emit(record); !written) return written;
  }
  entry.message_index_bytes = offset_ - start;
  return {};
}

std::string McapWriter::StatisticsContent() const {
  std::string counts;
  for (std::size_t channel_id = 0; channel_id < channel_message_counts_.size(); ++channel_id) {
    const std::uint64_t count = channel_message_counts_[channel_id];
    if (count == 0) continue;  // a channel without messages is not in the map
    AppendLittleEndian<std::uint16_t>(counts, static_cast<std::uint16_t>(channel_id));
    AppendLittleEndian<std::uint64_t>(counts, count);
  }
  std::string content;
  AppendLittleEndian<std::uint64_t>(content, message_count_);
  AppendLittleEndian<std::uint16_t>(content, static_cast<std::uint16_t>(schema_records_.size()));
  AppendLittleEndian<std::uint32_t>(content, static_cast<std::uint32_t>(channel_records_.size()));
  AppendLittleEndian<std::uint32_t>(content, 0);  // attachments
  AppendLittleEndian<std::uint32_t>(content, 0);  // metadata records
  AppendLittleEndian<std::uint32_t>(content, static_cast<std::uint32_t>(chunk_indexes_.size()));
  AppendLittleEndian<std::uint64_t>(content, message_start_ns_);
  AppendLittleEndian<std::uint64_t>(content, message_end_ns_);
  AppendString(content, counts);
  return content;
}

std::string McapWriter::ChunkIndexRecord(const ChunkIndexEntry& entry) const {
  std::string offsets;
  for (const auto& [channel_id, offset] : entry.message_index_offsets) {
    AppendLittleEndian<std::uint16_t>(offsets, channel_id);
    AppendLittleEndian<std::uint64_t>(offsets, offset);
  }
  std::string content;
  AppendLittleEndian<std::uint64_t>(content, entry.start_ns);
  AppendLittleEndian<std::uint64_t>(content, entry.end_ns);
  AppendLittleEndian<std::uint64_t>(content, entry.chunk_offset);
  AppendLittleEndian<std::uint64_t>(content, entry.chunk_record_bytes);
  AppendString(content, offsets);
  AppendLittleEndian<std::uint64_t>(content, entry.message_index_bytes);
  AppendString(content, CompressionName(options_.compression));
  AppendLittleEndian<std::uint64_t>(content, entry.compressed_bytes);
  AppendLittleEndian<std::uint64_t>(content, entry.uncompressed_bytes);
  std::string record;
  AppendRecord(record, Opcode::kChunkIndex, content);
  return record;
}

rig::Result<void> McapWriter::WriteSummaryAndFooter() {
  // The data section's CRC covers every byte from the leading magic up to DataEnd.
  std::string data_end;
  AppendRecordPrefix(data_end, Opcode::kDataEnd, 4);
  AppendLittleEndian<std::uint32_t>(data_end, running_crc_);
  if (auto written = Emit(data_end); !written) return written;

  const std::uint64_t summary_start = offset_;
  running_crc_ = 0;
  // Each group is one opcode's records; a SummaryOffset record points at each.
  std::string groups;
  const auto write_group = [&](Opcode opcode, const std::vector<std::string>& records) {
    if (records.empty()) return rig::Result<void>();
    const std::uint64_t start = offset_;
    for (const std::string& record : records) {
      if (auto written = Emit(record); !written) return written;
    }
    AppendRecordPrefix(groups, Opcode::kSummaryOffset, 1 + 8 + 8);
    groups.push_back(static_cast<char>(opcode));
    AppendLittleEndian<std::uint64_t>(groups, start);
    AppendLittleEndian<std::uint64_t>(groups, offset_ - start);
    return rig::Result<void>();
  };
  std::vector<std::string> statistics(1);
  AppendRecord(statistics[0], Opcode::kStatistics, StatisticsContent());
  std::vector<std::string> chunk_indexes;
  for (const ChunkIndexEntry& entry : chunk_indexes_)
    chunk_indexes.push_back(ChunkIndexRecord(entry));
  for (const auto& [opcode, records] :
       {std::pair{Opcode::kSchema, &schema_records_},
        std::pair{Opcode::kChannel, &channel_records_}, std::pair{Opcode::kStatistics, &statistics},
        std::pair{Opcode::kChunkIndex, &chunk_indexes}}) {
    if (auto written = write_group(opcode, *records); !written) return written;
  }
  const std::uint64_t summary_offset_start = offset_;
  if (auto written = Emit(groups); !written) return written;

  // The summary CRC runs from the summary's start through the Footer's summary_offset_start.
  std::string footer;
  AppendRecordPrefix(footer, Opcode::kFooter, kFooterContentBytes);
  AppendLittleEndian<std::uint64_t>(footer, summary_start);
  AppendLittleEndian<std::uint64_t>(footer, summary_offset_start);
  const std::uint32_t summary_crc = Crc32Update(running_crc_, footer);
  AppendLittleEndian<std::uint32_t>(footer, summary_crc);
  footer.append(kMagic);
  return Emit(footer);
}

rig::Result<void> McapWriter::Close() {
  if (closed_) return {};
  if (!open_) return WriterError("Close() before Open()");
  rig::Result<void> flushed = FlushChunk();
  if (flushed) flushed = Settle();
  StopWorker();
  closed_ = true;
  if (!flushed) return flushed;
  if (auto written = WriteSummaryAndFooter(); !written) return written;
  out_.flush();
  if (!out_) return rig::MakeError(rig::ErrorCode::kIo, "mcap writer: the stream refused a flush");
  return {};
}

}  // namespace hilrig::mcap
