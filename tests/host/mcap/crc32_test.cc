// CRC-32 against zlib's check values, and its incremental form.
#include "host/mcap/crc32.h"

#include <gtest/gtest.h>

namespace hilrig::mcap {
namespace {

TEST(Crc32Test, MatchesZlibCheckValues) {
  EXPECT_EQ(Crc32(""), 0u);
  EXPECT_EQ(Crc32("123456789"), 0xCBF43926u);
  EXPECT_EQ(Crc32("The quick brown fox jumps over the lazy dog"), 0x414FA339u);
  EXPECT_EQ(Crc32(std::string_view("\0", 1)), 0xD202EF8Du);
}

TEST(Crc32Test, UpdatingPieceByPieceEqualsTheWhole) {
  const std::string_view text = "The quick brown fox jumps over the lazy dog";
  for (std::size_t cut = 0; cut <= text.size(); ++cut) {
    EXPECT_EQ(Crc32Update(Crc32(text.substr(0, cut)), text.substr(cut)), Crc32(text)) << cut;
  }
}

}  // namespace
}  // namespace hilrig::mcap
