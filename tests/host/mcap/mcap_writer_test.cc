// The bytes McapWriter puts at the start and the end of a file, and its refusals.
#include "host/mcap/mcap_writer.h"

#include <gtest/gtest.h>

#include <sstream>

#include "host/mcap/mcap_format.h"
#include "tests/host/mcap/mcap_test_file.h"

namespace hilrig::mcap {
namespace {

std::uint64_t U64At(const std::string& bytes, std::size_t at) {
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < 8; ++i) {
    value |= static_cast<std::uint64_t>(static_cast<std::uint8_t>(bytes[at + i])) << (8 * i);
  }
  return value;
}

TEST(McapWriterTest, StartsWithTheMagicAndTheHeader) {
  const std::string bytes = testing::WriteTestFile(10, {});
  ASSERT_GT(bytes.size(), 100u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89MCAP0\r\n", 8));
  EXPECT_EQ(bytes[8], '\x01');
  // profile "x-hilrig" (4 + 8) and library "hilrig test" (4 + 11).
  EXPECT_EQ(U64At(bytes, 9), 4u + 8u + 4u + 11u);
  EXPECT_EQ(bytes.substr(17 + 4, 8), "x-hilrig");
}

TEST(McapWriterTest, EndsWithTheFooterAndTheMagic) {
  const std::string bytes = testing::WriteTestFile(10, {});
  const std::size_t footer = bytes.size() - 8 - 29;
  EXPECT_EQ(bytes.substr(bytes.size() - 8), std::string("\x89MCAP0\r\n", 8));
  EXPECT_EQ(bytes[footer], '\x02');
  EXPECT_EQ(U64At(bytes, footer + 1), 20u);
  const std::uint64_t summary_start = U64At(bytes, footer + 9);
  const std::uint64_t summary_offset_start = U64At(bytes, footer + 17);
  ASSERT_LT(summary_start, summary_offset_start);
  ASSERT_LT(summary_offset_start, footer);
  // DataEnd (opcode 0x0F, 4 bytes of content) ends where the summary starts.
  EXPECT_EQ(bytes[summary_start - 13], '\x0F');
  EXPECT_EQ(bytes[summary_offset_start], '\x0E');
}

MessageToWrite OnChannel(std::uint16_t channel_id, std::string_view payload = "{}") {
  MessageToWrite message;
  message.channel_id = channel_id;
  message.payload = payload;
  return message;
}

// Compressing on the writer's own thread changes when the bytes are written, not which: with small
// chunks (many in flight one after another) the file is the same byte for byte, zstd or stored.
TEST(McapWriterTest, WritingChunksInTheBackgroundGivesTheSameFile) {
  for (const ChunkCompression compression : {ChunkCompression::kZstd, ChunkCompression::kNone}) {
    McapWriterOptions options;
    options.compression = compression;
    options.chunk_bytes = 4096;
    const std::string inline_file = testing::WriteTestFile(5000, options);
    options.background = true;
    EXPECT_EQ(testing::WriteTestFile(5000, options), inline_file);
  }
}

TEST(McapWriterTest, RefusesWritesOutOfOrderAndUnknownChannels) {
  std::ostringstream out;
  McapWriter writer(out);
  EXPECT_FALSE(writer.Write(OnChannel(0)).ok());  // before Open()
  ASSERT_TRUE(writer.Open("", "").ok());
  EXPECT_FALSE(writer.AddChannel(7, "/t", "json").ok());  // no schema 7
  EXPECT_FALSE(writer.Write(OnChannel(0)).ok());
  ASSERT_TRUE(writer.AddChannel(0, "/t", "json").ok());
  EXPECT_TRUE(writer.Write(OnChannel(0)).ok());
  ASSERT_TRUE(writer.Close().ok());
  EXPECT_TRUE(writer.Close().ok());
  EXPECT_FALSE(writer.Write(OnChannel(0)).ok());
}

TEST(McapWriterTest, AFailingStreamIsAnIoError) {
  std::ostringstream out;
  out.setstate(std::ios::badbit);
  McapWriter writer(out);
  const rig::Result<void> opened = writer.Open("", "");
  ASSERT_FALSE(opened.ok());
  EXPECT_EQ(opened.error().code, rig::ErrorCode::kIo);
}

}  // namespace
}  // namespace hilrig::mcap
