// Shards: the I/N form, a partition of the cases, reading one row's line, and reading rows back
// from shards of which one was killed while writing.
#include "host/sweep/sweep_shard.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <optional>
#include <vector>

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

// Accepts every row that parsed.
std::optional<std::string> AnyRow(const proto::SweepCaseResult&) { return std::nullopt; }

TEST(ShardRowsTest, KeepsEveryWholeRowAndCountsACutLine) {
  const std::filesystem::path dir = FreshTestDir("shard_rows");
  std::filesystem::create_directories(dir / "shards");
  std::ofstream(dir / "shards" / "shard-0001-of-0002.jsonl")
      << "{\"index\":\"0\",\"scenario\":\"a\",\"outcome\":\"PASSED\"}\n"
         "{\"index\":\"2\",\"scenario\":\"a\",\"outcome\":\"FAILED\",\"wall_s\":1}\n";
  // Killed while writing its second row; and case 2 again from a run again, its timing aside the
  // same result: taken once.
  std::ofstream(dir / "shards" / "shard-0002-of-0002.jsonl")
      << "{\"index\":\"1\",\"scenario\":\"a\",\"outcome\":\"PASSED\"}\n"
         "{\"index\":\"3\",\"scen";
  std::ofstream(dir / "shards" / "shard-0003-of-0003.jsonl")
      << "{\"index\":\"2\",\"scenario\":\"a\",\"outcome\":\"FAILED\",\"wall_s\":2}\n";
  std::ofstream(dir / "shards" / "notes.txt") << "not a shard\n";
  auto rows = ReadShardRows(dir.string(), AnyRow);
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  EXPECT_EQ(rows.value().bad_lines, 1u);
  EXPECT_TRUE(rows.value().conflicting_cases.empty());
  ASSERT_EQ(rows.value().rows.size(), 3u);
  EXPECT_EQ(rows.value().rows.at(2).outcome(), proto::SweepCaseResult::FAILED);
  ASSERT_EQ(rows.value().problems.size(), 1u);
  EXPECT_THAT(rows.value().problems[0], HasSubstr("shards/shard-0002-of-0002.jsonl:2: "));
  auto missing = ReadShardRows((dir / "nothing").string(), AnyRow);
  ASSERT_FALSE(missing.ok());
  EXPECT_THAT(missing.error().message, HasSubstr("nothing/shards"));
}

TEST(ShardRowsTest, TwoDifferentRowsOfOneCaseStandForNeither) {
  const std::filesystem::path dir = FreshTestDir("shard_rows_conflict");
  std::filesystem::create_directories(dir / "shards");
  std::ofstream(dir / "shards" / "shard-0001-of-0001.jsonl")
      << "{\"index\":\"0\",\"scenario\":\"a\",\"outcome\":\"FAILED\"}\n"
         "{\"index\":\"0\",\"scenario\":\"a\",\"outcome\":\"PASSED\"}\n"
         "{\"index\":\"0\",\"scenario\":\"a\",\"outcome\":\"FAILED\"}\n"
         "{\"index\":\"1\",\"scenario\":\"a\",\"outcome\":\"PASSED\"}\n";
  auto rows = ReadShardRows(dir.string(), AnyRow);
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  EXPECT_EQ(rows.value().rows.count(0), 0u);  // not "the later one wins"
  EXPECT_EQ(rows.value().rows.count(1), 1u);
  EXPECT_EQ(rows.value().conflicting_cases, std::vector<std::uint64_t>{0});
  ASSERT_FALSE(rows.value().problems.empty());
  EXPECT_THAT(rows.value().problems[0], HasSubstr(":2: case 0 has two different rows"));
}

TEST(ShardRowsTest, ARowTheCheckRefusesStandsForNoCase) {
  const std::filesystem::path dir = FreshTestDir("shard_rows_check");
  std::filesystem::create_directories(dir / "shards");
  std::ofstream(dir / "shards" / "shard-0001-of-0001.jsonl")
      << "{}\n{\"index\":\"1\",\"scenario\":\"a\",\"outcome\":\"PASSED\"}\n";
  auto rows = ReadShardRows(dir.string(), [](const proto::SweepCaseResult& row) {
    return row.scenario() == "a" ? std::nullopt : std::optional<std::string>("not of a");
  });
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  EXPECT_EQ(rows.value().bad_lines, 1u);
  ASSERT_EQ(rows.value().rows.size(), 1u);
  EXPECT_EQ(rows.value().rows.count(0), 0u);  // the {} line does not stand for case 0
  EXPECT_THAT(rows.value().problems[0], HasSubstr("shard-0001-of-0001.jsonl:1: not of a"));
}

// A FIFO or a device planted among the shards is named and skipped, never waited on or read
// without end; a file of one endless line costs the cap, not the file.
TEST(ShardRowsTest, AFifoADeviceAndAnEndlessLineAreRefusedWithoutHangingOrFillingMemory) {
  const std::filesystem::path dir = FreshTestDir("shard_rows_hostile");
  std::filesystem::create_directories(dir / "shards");
  ASSERT_EQ(::mkfifo((dir / "shards" / "shard-0001-of-0004.jsonl").c_str(), 0600), 0);
  std::filesystem::create_symlink("/dev/zero", dir / "shards" / "shard-0002-of-0004.jsonl");
  std::ofstream(dir / "shards" / "shard-0003-of-0004.jsonl")
      << std::string(std::size_t{3} << 20, 'x');
  std::ofstream(dir / "shards" / "shard-0004-of-0004.jsonl")
      << "{\"index\":\"3\",\"scenario\":\"a\",\"outcome\":\"PASSED\"}\n";
  auto rows = ReadShardRows(dir.string(), AnyRow);
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  EXPECT_EQ(rows.value().unreadable_files, 2u);
  EXPECT_EQ(rows.value().bad_lines, 1u);
  EXPECT_EQ(rows.value().rows.size(), 1u);
  ASSERT_EQ(rows.value().problems.size(), 3u);
  EXPECT_THAT(rows.value().problems[0], HasSubstr("a FIFO, not a regular file"));
  EXPECT_THAT(rows.value().problems[1], HasSubstr("a device, not a regular file"));
  EXPECT_THAT(rows.value().problems[2], HasSubstr("a line longer than 1048576 bytes"));
}

}  // namespace
}  // namespace hilrig::host
