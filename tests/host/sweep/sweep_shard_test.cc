// Shards: the I/N form, a partition of the cases, reading one row's line, and reading rows back
// from shards of which one was killed while writing.
#include "host/sweep/sweep_shard.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

TEST(ShardSpecTest, ReadsIOfNFromOne) {
  auto shard = ParseShardSpec("2/5");
  ASSERT_TRUE(shard.ok()) << shard.error().message;
  EXPECT_EQ(shard.value().index, 1u);
  EXPECT_EQ(shard.value().count, 5u);
  for (const char* bad : {"", "1", "0/2", "3/2", "1/0", "a/b", "1/2/3", "1/100001", "-1/2"}) {
    auto parsed = ParseShardSpec(bad);
    ASSERT_FALSE(parsed.ok()) << bad;
    EXPECT_THAT(parsed.error().message, HasSubstr("expected I/N")) << bad;
  }
}

TEST(ShardSpecTest, EveryCaseIsInExactlyOneShard) {
  for (std::uint32_t count : {1u, 2u, 3u, 7u}) {
    for (std::uint64_t index = 0; index < 50; ++index) {
      int shards = 0;
      for (std::uint32_t i = 0; i < count; ++i) shards += InShard(index, {i, count}) ? 1 : 0;
      EXPECT_EQ(shards, 1) << index << " of " << count;
    }
  }
  EXPECT_THAT(ShardFile("out", {0, 12}), HasSubstr("out/shards/shard-0001-of-0012.jsonl"));
}

TEST(ShardRowTest, ReadsAWholeRow) {
  auto row = ParseShardRow("{\"index\":\"7\",\"scenario\":\"a\",\"outcome\":\"FAILED\"}");
  ASSERT_TRUE(row.ok()) << row.error().message;
  EXPECT_EQ(row.value().index(), 7u);
  EXPECT_EQ(row.value().scenario(), "a");
  EXPECT_EQ(row.value().outcome(), proto::SweepCaseResult::FAILED);
}

TEST(ShardRowTest, RefusesACutLineAndGarbage) {
  for (const char* bad :
       {"{\"index\":\"3\",\"scen", "not json", "{\"no_such_field\":1}", "[1,2]"}) {
    auto row = ParseShardRow(bad);
    ASSERT_FALSE(row.ok()) << bad;
    EXPECT_THAT(row.error().message, HasSubstr("not a case row")) << bad;
  }
  auto huge = ParseShardRow("{\"scenario\":\"" + std::string(std::size_t{1} << 20, 'a') + "\"}");
  ASSERT_FALSE(huge.ok());
  EXPECT_THAT(huge.error().message, HasSubstr("longer than any case row"));
}

TEST(ShardRowsTest, KeepsEveryWholeRowAndCountsACutLine) {
  const std::filesystem::path dir = FreshTestDir("shard_rows");
  std::filesystem::create_directories(dir / "shards");
  std::ofstream(dir / "shards" / "shard-0001-of-0002.jsonl")
      << "{\"index\":\"0\",\"scenario\":\"a\",\"outcome\":\"PASSED\"}\n"
         "{\"index\":\"2\",\"scenario\":\"a\",\"outcome\":\"FAILED\"}\n";
  // Killed while writing its second row; and a row of case 2 again, from a later run.
  std::ofstream(dir / "shards" / "shard-0002-of-0002.jsonl")
      << "{\"index\":\"1\",\"scenario\":\"a\",\"outcome\":\"PASSED\"}\n"
         "{\"index\":\"3\",\"scen";
  std::ofstream(dir / "shards" / "shard-0003-of-0003.jsonl")
      << "{\"index\":\"2\",\"scenario\":\"a\",\"outcome\":\"PASSED\"}\n";
  std::ofstream(dir / "shards" / "notes.txt") << "not a shard\n";
  std::uint64_t bad_lines = 0;
  auto rows = ReadShardRows(dir.string(), &bad_lines);
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  EXPECT_EQ(bad_lines, 1u);
  ASSERT_EQ(rows.value().size(), 3u);
  EXPECT_EQ(rows.value().at(2).outcome(), proto::SweepCaseResult::PASSED);
  auto missing = ReadShardRows((dir / "nothing").string(), nullptr);
  ASSERT_FALSE(missing.ok());
  EXPECT_THAT(missing.error().message, HasSubstr("nothing/shards"));
}

}  // namespace
}  // namespace hilrig::host
