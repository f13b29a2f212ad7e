#include "host/mcap/mcap_reader.h"

#include <zstd.h>

#include <fstream>
#include <utility>

#include "host/mcap/crc32.h"
#include "host/mcap/mcap_format.h"

namespace hilrig::mcap {
namespace {

using MaybeError = std::optional<McapError>;

McapError Fail(McapErrorKind kind, std::uint64_t offset, std::string detail) {
  return McapError{kind, offset, std::move(detail)};
}

// Reads little-endian fields off a record's content; each read fails, rather than reading past
// the end, when too few bytes are left.
class Cursor {
 public:
  explicit Cursor(std::string_view bytes) : bytes_(bytes) {}

  template <typename T>
  bool Read(T& value) {
    if (bytes_.size() < sizeof(T)) return false;
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      v |= static_cast<std::uint64_t>(static_cast<std::uint8_t>(bytes_[i])) << (8 * i);
    }
    value = static_cast<T>(v);
    bytes_.remove_prefix(sizeof(T));
    return true;
  }
  // <LengthType length><bytes>: a String, a Map or an Array (u32), a chunk's records (u64).
  template <typename LengthType>
  bool Prefixed(std::string_view& out) {
    LengthType length = 0;
    if (!Read(length) || length > bytes_.size()) return false;
    out = bytes_.substr(0, length);
    bytes_.remove_prefix(length);
    return true;
  }
  bool String(std::string& out) {
    std::string_view view;
    if (!Prefixed<std::uint32_t>(view)) return false;
    out.assign(view);
    return true;
  }
  std::string_view rest() const { return bytes_; }
  bool empty() const { return bytes_.empty(); }

 private:
  std::string_view bytes_;
};

struct Record {
  std::uint8_t opcode = 0;
  std::uint64_t offset = 0;  // of its opcode, in the file
  std::string_view content;
  std::uint64_t end() const { return offset + kRecordPrefixBytes + content.size(); }
};

// The record at `at` of `bytes`, or nothing when it runs past their end.
std::optional<Record> RecordAt(std::string_view bytes, std::uint64_t at, std::uint64_t base) {
  if (at > bytes.size() || bytes.size() - at < kRecordPrefixBytes) return std::nullopt;
  Cursor cursor(bytes.substr(at));
  Record record;
  std::uint64_t length = 0;
  cursor.Read(record.opcode);
  cursor.Read(length);
  if (length > cursor.rest().size()) return std::nullopt;
  record.offset = base + at;
  record.content = cursor.rest().substr(0, length);
  return record;
}

McapError Malformed(const Record& record, std::string_view what) {
  return Fail(McapErrorKind::kMalformedRecord, record.offset,
              std::string(what) + " record (opcode " + std::to_string(record.opcode) +
                  ") ends inside its fields");
}

// Everything the data section's records add to McapContents, with the checks each needs.
class RecordReader {
 public:
  RecordReader(const McapReadLimits& limits, McapContents& contents)
      : limits_(limits), contents_(contents) {}

  // A record of the data section, or of a chunk's records (`in_chunk`, located at the chunk).
  MaybeError Data(const Record& record, std::uint64_t located_at, bool in_chunk) {
    switch (static_cast<Opcode>(record.opcode)) {
      case Opcode::kSchema:
        return Schema(record, located_at);
      case Opcode::kChannel:
        return Channel(record, located_at);
      case Opcode::kMessage:
        return Message(record, located_at);
      case Opcode::kChunk:
        if (in_chunk)
          return Fail(McapErrorKind::kMalformedRecord, located_at, "a chunk in a chunk");
        return Chunk(record);
      default:
        return std::nullopt;  // indexes, attachments, metadata, unknown opcodes: not needed here
    }
  }

 private:
  MaybeError Schema(const Record& record, std::uint64_t located_at) {
    Cursor cursor(record.content);
    McapSchema schema;
    if (!cursor.Read(schema.id) || !cursor.String(schema.name) || !cursor.String(schema.encoding) ||
        !cursor.String(schema.data)) {
      return Malformed({record.opcode, located_at, record.content}, "a Schema");
    }
    if (schema.id != 0) contents_.schemas[schema.id] = std::move(schema);  // 0 is to be ignored
    return std::nullopt;
  }

  MaybeError Channel(const Record& record, std::uint64_t located_at) {
    Cursor cursor(record.content);
    McapChannel channel;
    std::string_view metadata;
    if (!cursor.Read(channel.id) || !cursor.Read(channel.schema_id) ||
        !cursor.String(channel.topic) || !cursor.String(channel.message_encoding) ||
        !cursor.Prefixed<std::uint32_t>(metadata)) {
      return Malformed({record.opcode, located_at, record.content}, "a Channel");
    }
    for (Cursor entries(metadata); !entries.empty();) {
      std::string key, value;
      if (!entries.String(key) || !entries.String(value)) {
        return Malformed({record.opcode, located_at, record.content}, "a Channel's metadata");
      }
      channel.metadata[std::move(key)] = std::move(value);
    }
    if (channel.schema_id != 0 && !contents_.schemas.contains(channel.schema_id)) {
      return Fail(
          McapErrorKind::kUnknownSchema, located_at,
          "channel " + channel.topic + " of unknown schema " + std::to_string(channel.schema_id));
    }
    contents_.channels[channel.id] = std::move(channel);
    return std::nullopt;
  }

  MaybeError Message(const Record& record, std::uint64_t located_at) {
    Cursor cursor(record.content);
    McapMessage message;
    if (!cursor.Read(message.channel_id) || !cursor.Read(message.sequence) ||
        !cursor.Read(message.log_time_ns) || !cursor.Read(message.publish_time_ns)) {
      return Malformed({record.opcode, located_at, record.content}, "a Message");
    }
    if (!contents_.channels.contains(message.channel_id)) {
      return Fail(McapErrorKind::kUnknownChannel, located_at,
                  "a message on unknown channel " + std::to_string(message.channel_id));
    }
    message.payload.assign(cursor.rest());
    contents_.messages.push_back(std::move(message));
    return std::nullopt;
  }

  MaybeError Chunk(const Record& record) {
    Cursor cursor(record.content);
    std::uint64_t start_ns = 0, end_ns = 0, uncompressed_bytes = 0;
    std::uint32_t crc = 0;
    std::string compression;
    std::string_view stored;
    if (!cursor.Read(start_ns) || !cursor.Read(end_ns) || !cursor.Read(uncompressed_bytes) ||
        !cursor.Read(crc) || !cursor.String(compression) ||
        !cursor.Prefixed<std::uint64_t>(stored)) {
      return Malformed(record, "a Chunk");
    }
    if (uncompressed_bytes > limits_.max_chunk_uncompressed_bytes ||
        uncompressed_bytes > limits_.max_total_uncompressed_bytes - total_uncompressed_bytes_) {
      return Fail(McapErrorKind::kTooLarge, record.offset,
                  "a chunk of " + std::to_string(uncompressed_bytes) +
                      " uncompressed bytes is past the read limits");
    }
    total_uncompressed_bytes_ += uncompressed_bytes;
    if (MaybeError error = Decompress(record.offset, compression, stored, uncompressed_bytes)) {
      return error;
    }
    const std::string_view view = view_;
    if (crc != 0 && Crc32(view) != crc) {
      return Fail(McapErrorKind::kChunkCrcMismatch, record.offset,
                  "a chunk's records do not have its CRC-32");
    }
    ++contents_.chunk_count;
    for (std::uint64_t at = 0; at < view.size();) {
      const std::optional<Record> inner = RecordAt(view, at, 0);
      if (!inner.has_value()) {
        return Fail(McapErrorKind::kMalformedRecord, record.offset,
                    "a record at " + std::to_string(at) + " of a chunk's records runs past them");
      }
      if (MaybeError error = Data(*inner, record.offset, true)) return error;
      at = inner->end();
    }
    return std::nullopt;
  }

  // Sets view_ to the chunk's records: as stored, or decompressed into decompressed_; an error
  // when they are not `uncompressed_bytes` long.
  MaybeError Decompress(std::uint64_t offset, const std::string& compression,
                        std::string_view stored, std::uint64_t uncompressed_bytes) {
    if (compression.empty()) {
      view_ = stored;
    } else if (compression == "zstd") {
      decompressed_.resize(uncompressed_bytes);
      const std::size_t size =
          ZSTD_decompress(decompressed_.data(), decompressed_.size(), stored.data(), stored.size());
      if (ZSTD_isError(size) != 0) {
        return Fail(McapErrorKind::kBadCompressedData, offset,
                    std::string("zstd refused a chunk: ") + ZSTD_getErrorName(size));
      }
      view_ = std::string_view(decompressed_.data(), size);
    } else {
      return Fail(McapErrorKind::kUnknownCompression, offset,
                  "a chunk compressed with \"" + compression + "\"");
    }
    if (view_.size() != uncompressed_bytes) {
      return Fail(McapErrorKind::kBadCompressedData, offset,
                  "a chunk's records are " + std::to_string(view_.size()) + " bytes, not the " +
                      std::to_string(uncompressed_bytes) + " it states");
    }
    return std::nullopt;
  }

  const McapReadLimits& limits_;
  McapContents& contents_;
  std::string decompressed_;  // reused for every chunk
  std::string_view view_;
  std::uint64_t total_uncompressed_bytes_ = 0;
};

// How a walk over the data section ended.
struct DataWalk {
  MaybeError error;
  bool reached_data_end = false;
  std::uint64_t end = 0;  // past DataEnd, or where the first incomplete record starts
};

// The records from the Header to DataEnd, all within `bytes`. With `tolerate_incomplete`, a record
// that runs past `bytes` ends the walk where it starts; otherwise it is an error.
DataWalk WalkDataSection(std::string_view bytes, bool tolerate_incomplete, RecordReader& reader,
                         McapContents& contents) {
  DataWalk walk;
  std::uint64_t at = kMagic.size();
  bool first = true;
  while (true) {
    const std::optional<Record> record = RecordAt(bytes, at, 0);
    if (!record.has_value()) {
      walk.end = at;
      if (!tolerate_incomplete) {
        walk.error = Fail(first ? McapErrorKind::kTruncated : McapErrorKind::kMissingDataEnd, at,
                          "the data section ends inside a record, before DataEnd");
      }
      return walk;
    }
    if (first) {
      Cursor header(record->content);
      if (record->opcode != static_cast<std::uint8_t>(Opcode::kHeader) ||
          !header.String(contents.profile) || !header.String(contents.library)) {
        walk.error = Fail(McapErrorKind::kMalformedRecord, at, "the first record is no Header");
        return walk;
      }
      first = false;
    } else if (record->opcode == static_cast<std::uint8_t>(Opcode::kDataEnd)) {
      Cursor data_end(record->content);
      std::uint32_t crc = 0;
      if (!data_end.Read(crc)) {
        walk.error = Malformed(*record, "the DataEnd");
      } else if (crc != 0 && crc != Crc32(bytes.substr(0, at))) {
        walk.error = Fail(McapErrorKind::kDataCrcMismatch, at,
                          "DataEnd's CRC-32 is not that of the data section");
      }
      walk.reached_data_end = true;
      walk.end = record->end();
      return walk;
    } else if (MaybeError error = reader.Data(*record, record->offset, false)) {
      walk.error = std::move(error);
      return walk;
    }
    at = record->end();
  }
}

struct Footer {
  std::uint64_t offset = 0;
  std::uint64_t summary_start = 0;
  std::uint64_t summary_offset_start = 0;
  std::uint32_t summary_crc = 0;
};

std::optional<Footer> FooterOf(std::string_view bytes) {
  if (bytes.size() < 2 * kMagic.size() + kFooterRecordBytes) return std::nullopt;
  Footer footer;
  footer.offset = bytes.size() - kMagic.size() - kFooterRecordBytes;
  const std::optional<Record> record = RecordAt(bytes, footer.offset, 0);
  if (!record.has_value() || record->opcode != static_cast<std::uint8_t>(Opcode::kFooter) ||
      record->content.size() != kFooterContentBytes) {
    return std::nullopt;
  }
  Cursor cursor(record->content);
  cursor.Read(footer.summary_start);
  cursor.Read(footer.summary_offset_start);
  cursor.Read(footer.summary_crc);
  return footer;
}

MaybeError ReadStatistics(const Record& record, McapStatistics& statistics) {
  Cursor cursor(record.content);
  std::uint32_t attachments = 0, metadata = 0;
  std::string_view counts;
  if (!cursor.Read(statistics.message_count) || !cursor.Read(statistics.schema_count) ||
      !cursor.Read(statistics.channel_count) || !cursor.Read(attachments) ||
      !cursor.Read(metadata) || !cursor.Read(statistics.chunk_count) ||
      !cursor.Read(statistics.message_start_ns) || !cursor.Read(statistics.message_end_ns) ||
      !cursor.Prefixed<std::uint32_t>(counts)) {
    return Malformed(record, "the Statistics");
  }
  for (Cursor entries(counts); !entries.empty();) {
    std::uint16_t channel_id = 0;
    std::uint64_t count = 0;
    if (!entries.Read(channel_id) || !entries.Read(count)) {
      return Malformed(record, "the Statistics' channel counts of");
    }
    statistics.channel_message_counts[channel_id] = count;
  }
  return std::nullopt;
}

// The summary section, from its start to the Footer: its CRC, then its Statistics and ChunkIndex
// records (Schema and Channel records repeat the data section's; SummaryOffsets only point).
MaybeError ReadSummary(std::string_view bytes, const Footer& footer, std::uint64_t data_end,
                       McapContents& contents) {
  if (footer.summary_start == 0) return std::nullopt;
  if (footer.summary_start < data_end || footer.summary_start > footer.offset ||
      (footer.summary_offset_start != 0 && (footer.summary_offset_start < footer.summary_start ||
                                            footer.summary_offset_start > footer.offset))) {
    return Fail(McapErrorKind::kBadFooter, footer.offset,
                "the Footer's summary offsets lie outside the summary");
  }
  const std::uint64_t crc_end = footer.offset + kRecordPrefixBytes + 8 + 8;
  if (footer.summary_crc != 0 &&
      Crc32(bytes.substr(footer.summary_start, crc_end - footer.summary_start)) !=
          footer.summary_crc) {
    return Fail(McapErrorKind::kSummaryCrcMismatch, footer.summary_start,
                "the Footer's CRC-32 is not that of the summary");
  }
  const std::uint64_t records_end =
      footer.summary_offset_start != 0 ? footer.summary_offset_start : footer.offset;
  const std::string_view summary = bytes.substr(0, records_end);
  for (std::uint64_t at = footer.summary_start; at < records_end;) {
    const std::optional<Record> record = RecordAt(summary, at, 0);
    if (!record.has_value()) {
      return Fail(McapErrorKind::kTruncated, at, "a summary record runs past the summary");
    }
    if (record->opcode == static_cast<std::uint8_t>(Opcode::kStatistics)) {
      McapStatistics statistics;
      if (MaybeError error = ReadStatistics(*record, statistics)) return error;
      contents.statistics = std::move(statistics);
    } else if (record->opcode == static_cast<std::uint8_t>(Opcode::kChunkIndex)) {
      ++contents.chunk_index_count;
    }
    at = record->end();
  }
  return std::nullopt;
}

bool HasMagicAtBothEnds(std::string_view bytes) {
  return bytes.size() >= 2 * kMagic.size() && bytes.starts_with(kMagic) && bytes.ends_with(kMagic);
}

McapReadResult WithError(McapError error) {
  McapReadResult result;
  result.error = std::move(error);
  return result;
}

}  // namespace

McapReadResult ReadMcap(std::string_view bytes, const McapReadLimits& limits) {
  if (!HasMagicAtBothEnds(bytes)) {
    return WithError(Fail(McapErrorKind::kBadMagic, bytes.starts_with(kMagic) ? bytes.size() : 0,
                          "no MCAP magic at both ends"));
  }
  const std::optional<Footer> footer = FooterOf(bytes);
  if (!footer.has_value()) {
    return WithError(Fail(McapErrorKind::kBadFooter, bytes.size() - kMagic.size(),
                          "no Footer before the closing magic"));
  }
  McapReadResult result;
  RecordReader reader(limits, result.contents);
  const std::uint64_t data_limit =
      footer->summary_start != 0 && footer->summary_start <= footer->offset ? footer->summary_start
                                                                            : footer->offset;
  DataWalk walk = WalkDataSection(bytes.substr(0, data_limit), false, reader, result.contents);
  if (walk.error.has_value()) {
    result.error = std::move(walk.error);
  } else {
    result.error = ReadSummary(bytes, *footer, walk.end, result.contents);
  }
  result.contents.complete_bytes = bytes.size();
  return result;
}

McapReadResult RecoverMcap(std::string_view bytes, const McapReadLimits& limits) {
  // A file with its closing magic was written to the end: it reads, or fails, as a whole file.
  if (HasMagicAtBothEnds(bytes) && FooterOf(bytes).has_value()) return ReadMcap(bytes, limits);
  McapReadResult result;
  result.contents.truncated = true;
  if (!bytes.starts_with(kMagic)) {
    // Killed before the magic was out: nothing was written, which is not a malformed file.
    if (kMagic.starts_with(bytes)) return result;
    return WithError(Fail(McapErrorKind::kBadMagic, 0, "no MCAP magic at the start"));
  }
  RecordReader reader(limits, result.contents);
  DataWalk walk = WalkDataSection(bytes, true, reader, result.contents);
  result.error = std::move(walk.error);
  result.contents.complete_bytes = walk.end;
  return result;
}

McapReadResult ReadMcapFile(const std::filesystem::path& path, bool recover,
                            const McapReadLimits& limits) {
  std::error_code code;
  const std::uintmax_t size = std::filesystem::file_size(path, code);
  if (code) {
    return WithError(
        Fail(McapErrorKind::kUnreadableFile, 0, path.string() + ": " + code.message()));
  }
  if (size > limits.max_file_bytes) {
    return WithError(
        Fail(McapErrorKind::kTooLarge, 0,
             path.string() + " is " + std::to_string(size) + " bytes, past the limit"));
  }
  std::string bytes(size, '\0');
  std::ifstream in(path, std::ios::binary);
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size))) {
    return WithError(Fail(McapErrorKind::kUnreadableFile, 0, path.string() + ": read failed"));
  }
  return recover ? RecoverMcap(bytes, limits) : ReadMcap(bytes, limits);
}

}  // namespace hilrig::mcap
