// CRC-32 against zlib's check values and a bit-at-a-time reference over every length and
// alignment around the folded path's edges, and its incremental form.
#include "host/mcap/crc32.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>

namespace hilrig::mcap {
namespace {

// The CRC by its definition, one bit at a time: slow, and sharing nothing with the code tested.
std::uint32_t BitwiseCrc32(std::string_view bytes) {
  std::uint32_t state = 0xFFFFFFFFu;
  for (const char byte : bytes) {
    state ^= static_cast<std::uint8_t>(byte);
    for (int bit = 0; bit < 8; ++bit) state = (state >> 1) ^ (0xEDB88320u & (0u - (state & 1u)));
  }
  return ~state;
}

std::string RandomBytes(std::size_t size, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::string bytes(size, '\0');
  for (char& byte : bytes) byte = static_cast<char>(random() & 0xFFu);
  return bytes;
}

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

TEST(Crc32Test, MatchesTheDefinitionAtEveryLengthAndAlignment) {
  const std::string bytes = RandomBytes(1200, 7);
  for (std::size_t offset = 0; offset < 16; ++offset) {
    for (std::size_t size = 0; size + offset <= 1100; ++size) {
      const std::string_view piece = std::string_view(bytes).substr(offset, size);
      ASSERT_EQ(Crc32(piece), BitwiseCrc32(piece)) << "offset " << offset << " size " << size;
    }
  }
}

TEST(Crc32Test, MatchesTheDefinitionOverAChunk) {
  for (const std::size_t size : {std::size_t{1} << 20, (std::size_t{1} << 20) + 13}) {
    const std::string bytes = RandomBytes(size, static_cast<std::uint32_t>(size));
    EXPECT_EQ(Crc32(bytes), BitwiseCrc32(bytes)) << size;
    const std::string zeros(size, '\0');
    EXPECT_EQ(Crc32(zeros), BitwiseCrc32(zeros)) << size;
  }
}

TEST(Crc32Test, LongPiecesChainAsTheWhole) {
  const std::string bytes = RandomBytes(5000, 11);
  for (const std::size_t cut : {1, 63, 64, 255, 256, 257, 1000, 4744, 4999}) {
    EXPECT_EQ(Crc32Update(Crc32(std::string_view(bytes).substr(0, cut)),
                          std::string_view(bytes).substr(cut)),
              BitwiseCrc32(bytes))
        << cut;
  }
}

}  // namespace
}  // namespace hilrig::mcap
