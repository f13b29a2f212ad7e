// McapWriter's files read back whole by ReadMcap, cut ones by RecoverMcap, and each kind of damage
// found where it is.
#include "host/mcap/mcap_reader.h"

#include <gtest/gtest.h>

#include "host/mcap/mcap_format.h"
#include "tests/host/mcap/mcap_test_file.h"

namespace hilrig::mcap {
namespace {

constexpr std::size_t kMessages = 3000;
McapWriterOptions SmallChunks(ChunkCompression compression) {
  McapWriterOptions options;
  options.compression = compression;
  options.chunk_bytes = 4096;
  return options;
}
const McapWriterOptions kSmallZstdChunks = SmallChunks(ChunkCompression::kZstd);
const McapWriterOptions kSmallStoredChunks = SmallChunks(ChunkCompression::kNone);

void ExpectAllMessages(const McapContents& contents, std::size_t count) {
  ASSERT_EQ(contents.messages.size(), count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::string payload = testing::PayloadOf(i);
    const MessageToWrite expected = testing::NthMessage(i, payload);
    const McapMessage& got = contents.messages[i];
    ASSERT_EQ(got.channel_id, expected.channel_id) << i;
    ASSERT_EQ(got.sequence, expected.sequence) << i;
    ASSERT_EQ(got.log_time_ns, expected.log_time_ns) << i;
    ASSERT_EQ(got.publish_time_ns, expected.publish_time_ns) << i;
    ASSERT_EQ(got.payload, payload) << i;
  }
}

void ExpectRoundTrip(const McapWriterOptions& options) {
  const std::string bytes = testing::WriteTestFile(kMessages, options);
  const McapReadResult read = ReadMcap(bytes);
  ASSERT_TRUE(read.ok()) << read.error->detail;
  const McapContents& contents = read.contents;
  EXPECT_EQ(contents.profile, "x-hilrig");
  EXPECT_EQ(contents.library, "hilrig test");
  ASSERT_EQ(contents.schemas.size(), 2u);
  EXPECT_EQ(contents.schemas.at(1).name, "State");
  EXPECT_EQ(contents.schemas.at(1).data, "{\"type\":\"object\"}");
  ASSERT_EQ(contents.channels.size(), 3u);
  EXPECT_EQ(contents.channels.at(0).topic, "/plant/state");
  EXPECT_EQ(contents.channels.at(0).metadata.at("rate_hz"), "250");
  EXPECT_EQ(contents.channels.at(2).schema_id, 0);
  ExpectAllMessages(contents, kMessages);
  EXPECT_GT(contents.chunk_count, 10u);
  EXPECT_EQ(contents.chunk_index_count, contents.chunk_count);

  ASSERT_TRUE(contents.statistics.has_value());
  const McapStatistics& statistics = *contents.statistics;
  EXPECT_EQ(statistics.message_count, kMessages);
  EXPECT_EQ(statistics.schema_count, 2);
  EXPECT_EQ(statistics.channel_count, 3u);
  EXPECT_EQ(statistics.chunk_count, contents.chunk_count);
  EXPECT_EQ(statistics.message_start_ns, contents.messages.front().log_time_ns);
  EXPECT_EQ(statistics.message_end_ns, contents.messages.back().log_time_ns);
  const std::map<std::uint16_t, std::uint64_t> per_channel{{0, 1000}, {1, 1000}, {2, 1000}};
  EXPECT_EQ(statistics.channel_message_counts, per_channel);
}

TEST(McapReaderTest, ZstdChunksRoundTrip) { ExpectRoundTrip(kSmallZstdChunks); }
TEST(McapReaderTest, StoredChunksRoundTrip) { ExpectRoundTrip(kSmallStoredChunks); }

TEST(McapReaderTest, ZstdChunksAreSmallerThanStoredOnes) {
  EXPECT_LT(testing::WriteTestFile(kMessages, kSmallZstdChunks).size() * 2,
            testing::WriteTestFile(kMessages, kSmallStoredChunks).size());
}

TEST(McapReaderTest, AFileWithoutMessagesReads) {
  const McapReadResult read = ReadMcap(testing::WriteTestFile(0, {}));
  ASSERT_TRUE(read.ok()) << read.error->detail;
  EXPECT_EQ(read.contents.chunk_count, 0u);
  EXPECT_EQ(read.contents.statistics->message_count, 0u);
}

// The offset of the first byte of `needle` in `bytes`.
std::size_t Find(const std::string& bytes, std::string_view needle) {
  const std::size_t at = bytes.find(needle);
  HILRIG_CHECK(at != std::string::npos, "no such bytes in the file");
  return at;
}

void ExpectError(const std::string& bytes, McapErrorKind kind) {
  const McapReadResult read = ReadMcap(bytes);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error->kind, kind) << read.error->detail;
}

TEST(McapReaderTest, AFlippedByteInAChunkIsThatChunksCrcError) {
  std::string bytes = testing::WriteTestFile(kMessages, kSmallStoredChunks);
  const std::size_t at = Find(bytes, testing::PayloadOf(1500));
  bytes[at + 2] ^= 0x01;
  const McapReadResult read = ReadMcap(bytes);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error->kind, McapErrorKind::kChunkCrcMismatch);
  // Located at the chunk that holds the byte: within a chunk's length before it.
  EXPECT_LT(read.error->offset, at);
  EXPECT_GT(read.error->offset + 4096 + 200, at);
}

TEST(McapReaderTest, AFlippedByteInAZstdChunkIsFound) {
  std::string bytes = testing::WriteTestFile(kMessages, kSmallZstdChunks);
  bytes[bytes.size() / 2] ^= 0x10;
  const McapReadResult read = ReadMcap(bytes);
  ASSERT_FALSE(read.ok());
  EXPECT_TRUE(read.error->kind == McapErrorKind::kChunkCrcMismatch ||
              read.error->kind == McapErrorKind::kBadCompressedData ||
              read.error->kind == McapErrorKind::kDataCrcMismatch)
      << read.error->detail;
}

TEST(McapReaderTest, AFlippedByteInTheHeaderIsTheDataSectionsCrcError) {
  std::string bytes = testing::WriteTestFile(30, {});
  bytes[Find(bytes, "x-hilrig")] = 'y';
  ExpectError(bytes, McapErrorKind::kDataCrcMismatch);
}

TEST(McapReaderTest, AFlippedByteInTheSummaryIsTheSummarysCrcError) {
  std::string bytes = testing::WriteTestFile(kMessages, kSmallZstdChunks);
  bytes[bytes.size() - 8 - 29 - 30] ^= 0x01;  // a SummaryOffset's bytes
  ExpectError(bytes, McapErrorKind::kSummaryCrcMismatch);
  std::string channel_copy = testing::WriteTestFile(kMessages, kSmallZstdChunks);
  channel_copy[channel_copy.rfind("/run/events")] = '_';  // the summary's Channel record
  ExpectError(channel_copy, McapErrorKind::kSummaryCrcMismatch);
}

TEST(McapReaderTest, MissingMagicOrFooterIsRefused) {
  const std::string bytes = testing::WriteTestFile(30, {});
  ExpectError(bytes.substr(1), McapErrorKind::kBadMagic);
  ExpectError(bytes.substr(0, bytes.size() - 1), McapErrorKind::kBadMagic);
  ExpectError("", McapErrorKind::kBadMagic);
  std::string no_footer = bytes;
  no_footer[no_footer.size() - 8 - 29] = '\x7F';
  ExpectError(no_footer, McapErrorKind::kBadFooter);
}

TEST(McapReaderTest, AChunkPastTheLimitsIsRefusedBeforeItIsDecompressed) {
  const std::string bytes = testing::WriteTestFile(kMessages, kSmallZstdChunks);
  McapReadLimits chunk_limit;
  chunk_limit.max_chunk_uncompressed_bytes = 1000;
  const McapReadResult read = ReadMcap(bytes, chunk_limit);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error->kind, McapErrorKind::kTooLarge);
  McapReadLimits total_limit;
  total_limit.max_total_uncompressed_bytes = 50'000;
  const McapReadResult total = ReadMcap(bytes, total_limit);
  ASSERT_FALSE(total.ok());
  EXPECT_EQ(total.error->kind, McapErrorKind::kTooLarge);
}

// A file built record by record: the magic, a Header, `records`, DataEnd and Footer without CRCs.
std::string HandMadeFile(const std::string& records) {
  std::string bytes(kMagic);
  std::string header;
  AppendString(header, "");
  AppendString(header, "");
  AppendRecord(bytes, Opcode::kHeader, header);
  bytes += records;
  AppendRecord(bytes, Opcode::kDataEnd, std::string(4, '\0'));
  AppendRecord(bytes, Opcode::kFooter, std::string(kFooterContentBytes, '\0'));
  return bytes + std::string(kMagic);
}

std::string ChannelRecord(std::uint16_t id) {
  std::string content;
  AppendLittleEndian<std::uint16_t>(content, id);
  AppendLittleEndian<std::uint16_t>(content, 0);
  AppendString(content, "/t");
  AppendString(content, "json");
  AppendString(content, "");
  std::string record;
  AppendRecord(record, Opcode::kChannel, content);
  return record;
}

std::string MessageRecord(std::uint16_t channel_id) {
  std::string content;
  AppendLittleEndian<std::uint16_t>(content, channel_id);
  content += std::string(kMessageFixedBytes - 2, '\0') + "{}";
  std::string record;
  AppendRecord(record, Opcode::kMessage, content);
  return record;
}

TEST(McapReaderTest, UnknownOpcodesAreSkipped) {
  std::string extension;
  AppendRecord(extension, static_cast<Opcode>(0x80), "anything");
  const McapReadResult read =
      ReadMcap(HandMadeFile(ChannelRecord(3) + extension + MessageRecord(3)));
  ASSERT_TRUE(read.ok()) << read.error->detail;
  ASSERT_EQ(read.contents.messages.size(), 1u);
  EXPECT_EQ(read.contents.messages[0].payload, "{}");
}

TEST(McapReaderTest, AMessageOnAnUnknownChannelIsLocated) {
  const std::string channel = ChannelRecord(3);
  const McapReadResult read = ReadMcap(HandMadeFile(channel + MessageRecord(4)));
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error->kind, McapErrorKind::kUnknownChannel);
  EXPECT_EQ(read.error->offset, kMagic.size() + kRecordPrefixBytes + 8 + channel.size());
}

TEST(McapReaderTest, ARecordLongerThanTheFileIsTruncated) {
  std::string record;
  AppendRecordPrefix(record, Opcode::kChannel, 1ull << 60);
  const McapReadResult read = ReadMcap(HandMadeFile(record));
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error->kind, McapErrorKind::kMissingDataEnd);
  EXPECT_EQ(read.error->offset, kMagic.size() + kRecordPrefixBytes + 8);
}

TEST(McapReaderTest, AFieldPastItsRecordIsMalformed) {
  std::string record;
  AppendRecord(record, Opcode::kChannel, std::string("\x01\x00\x00\x00\xFF\xFF\x00\x00", 8));
  ExpectError(HandMadeFile(record), McapErrorKind::kMalformedRecord);
}

TEST(McapReaderTest, ACutFileRecoversItsCompleteChunks) {
  const std::string bytes = testing::WriteTestFile(kMessages, kSmallZstdChunks);
  std::size_t previous = 0;
  for (const std::size_t cut : {bytes.size() / 4, bytes.size() / 2, bytes.size() * 3 / 4}) {
    const McapReadResult read = RecoverMcap(bytes.substr(0, cut));
    ASSERT_TRUE(read.ok()) << read.error->detail;
    EXPECT_TRUE(read.contents.truncated);
    EXPECT_LE(read.contents.complete_bytes, cut);
    EXPECT_EQ(read.contents.channels.size(), 3u);
    const std::size_t count = read.contents.messages.size();
    EXPECT_GT(count, previous);
    EXPECT_LT(count, kMessages);
    ExpectAllMessages(read.contents, count);
    // What was recovered is exactly the complete records: cut there, nothing more is lost.
    const McapReadResult again = RecoverMcap(bytes.substr(0, read.contents.complete_bytes));
    EXPECT_EQ(again.contents.messages.size(), count);
    previous = count;
  }
  // Cut inside the summary: every chunk is complete.
  const McapReadResult read = RecoverMcap(bytes.substr(0, bytes.size() - 40));
  ASSERT_TRUE(read.ok()) << read.error->detail;
  EXPECT_TRUE(read.contents.truncated);
  ExpectAllMessages(read.contents, kMessages);
}

TEST(McapReaderTest, RecoveringAWholeFileReadsItWhole) {
  const McapReadResult read = RecoverMcap(testing::WriteTestFile(300, kSmallZstdChunks));
  ASSERT_TRUE(read.ok());
  EXPECT_FALSE(read.contents.truncated);
  EXPECT_TRUE(read.contents.statistics.has_value());
  ExpectAllMessages(read.contents, 300);
}

TEST(McapReaderTest, RecoveringACutFileStillFindsDamage) {
  std::string bytes = testing::WriteTestFile(kMessages, kSmallStoredChunks);
  bytes[Find(bytes, testing::PayloadOf(10)) + 2] ^= 0x01;
  const McapReadResult read = RecoverMcap(bytes.substr(0, bytes.size() / 2));
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error->kind, McapErrorKind::kChunkCrcMismatch);
}

TEST(McapReaderTest, AFileKilledBeforeItsMagicRecoversEmpty) {
  const McapReadResult read = RecoverMcap(std::string(kMagic.substr(0, 3)));
  ASSERT_TRUE(read.ok());
  EXPECT_TRUE(read.contents.truncated);
  EXPECT_TRUE(read.contents.messages.empty());
}

}  // namespace
}  // namespace hilrig::mcap
