#include "host/mcap/crc32.h"

#include <array>

namespace hilrig::mcap {
namespace {

constexpr std::uint32_t kReflectedPolynomial = 0xEDB88320u;

constexpr std::array<std::uint32_t, 256> MakeTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t byte = 0; byte < 256; ++byte) {
    std::uint32_t value = byte;
    for (int bit = 0; bit < 8; ++bit) {
      value = (value & 1u) != 0 ? (value >> 1) ^ kReflectedPolynomial : value >> 1;
    }
    table[byte] = value;
  }
  return table;
}

constexpr std::array<std::uint32_t, 256> kTable = MakeTable();

}  // namespace

std::uint32_t Crc32Update(std::uint32_t crc, std::string_view bytes) {
  // The register is kept inverted between calls, as zlib's crc32() does, so that 0 starts it.
  std::uint32_t value = ~crc;
  for (const char c : bytes) {
    value = kTable[(value ^ static_cast<std::uint8_t>(c)) & 0xFFu] ^ (value >> 8);
  }
  return ~value;
}

}  // namespace hilrig::mcap
