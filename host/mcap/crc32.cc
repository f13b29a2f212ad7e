#include "host/mcap/crc32.h"

#include <zlib.h>

#include <array>
#include <cstring>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace hilrig::mcap {
namespace {

std::uint32_t ZlibCrc32(std::uint32_t crc, const char* data, std::size_t size) {
  return static_cast<std::uint32_t>(crc32_z(crc, reinterpret_cast<const Bytef*>(data), size));
}

#if defined(__x86_64__)

// Folding with carry-less multiplication. In the reflected bit order of this CRC a 16-byte block
// loaded little-endian holds bit i as the coefficient of x^(127 - i) (its first bit is its
// highest power). A block V standing D bits before another may be replaced by V * x^D mod P,
// added onto that other block, without changing the remainder of the whole; with V = h x^64 + l
// (h its low 8 bytes) that is h * (x^(64+D) mod P) + l * (x^D mod P): two 64 x 32-bit carry-less
// products. The bytes are folded four blocks at a time into four lanes, the lanes into one, and
// that last block's remainder, and the tail's, come from zlib.

// x^exponent mod P, P = x^32 + 0x04C11DB7, bit b the coefficient of x^b.
constexpr std::uint64_t PowerModP(unsigned exponent) {
  std::uint64_t r = 1;
  for (unsigned i = 0; i < exponent; ++i) {
    r <<= 1;
    if ((r >> 32) != 0) r ^= 0x104C11DB7u;
  }
  return r;
}

// The multiplier that moves a 64-bit half forward by `exponent` bits, reflected into a 64-bit
// operand (bit j the coefficient of x^(63 - j)). A reflected product of two 64-bit operands comes
// out one power short in a 128-bit register (its bit 127 is always clear), so the constant is
// x^(exponent - 1) mod P.
constexpr std::uint64_t FoldConstant(unsigned exponent) {
  const std::uint64_t remainder = PowerModP(exponent - 1);
  std::uint64_t reflected = 0;
  for (unsigned b = 0; b < 32; ++b) {
    if (((remainder >> b) & 1u) != 0) reflected |= std::uint64_t{1} << (63 - b);
  }
  return reflected;
}

// The pair of multipliers that fold a block `bits` forward: low half by 64 + bits, high by bits.
struct FoldBy {
  std::uint64_t low, high;
};
constexpr FoldBy kFold128{FoldConstant(64 + 128), FoldConstant(128)};
constexpr FoldBy kFold256{FoldConstant(64 + 256), FoldConstant(256)};
constexpr FoldBy kFold384{FoldConstant(64 + 384), FoldConstant(384)};
constexpr FoldBy kFold512{FoldConstant(64 + 512), FoldConstant(512)};

__attribute__((target("pclmul,sse2"))) inline __m128i Fold(__m128i block, const __m128i& by) {
  return _mm_xor_si128(_mm_clmulepi64_si128(block, by, 0x00),
                       _mm_clmulepi64_si128(block, by, 0x11));
}

__attribute__((target("pclmul,sse2"))) inline __m128i Multipliers(const FoldBy& fold) {
  return _mm_set_epi64x(static_cast<long long>(fold.high), static_cast<long long>(fold.low));
}

__attribute__((target("pclmul,sse2"))) inline __m128i Load(const char* at) {
  return _mm_loadu_si128(reinterpret_cast<const __m128i*>(at));
}

// `size` at least 64. O(size); no allocation.
__attribute__((target("pclmul,sse2"))) std::uint32_t FoldedCrc32(std::uint32_t crc,
                                                                 const char* data,
                                                                 std::size_t size) {
  const __m128i by512 = Multipliers(kFold512);
  // The register's start value (inverted) added onto the first 32 bits, as a CRC does.
  __m128i lanes[4] = {_mm_xor_si128(Load(data), _mm_cvtsi32_si128(static_cast<int>(~crc))),
                      Load(data + 16), Load(data + 32), Load(data + 48)};
  std::size_t at = 64;
  for (; size - at >= 64; at += 64) {
    for (int lane = 0; lane < 4; ++lane) {
      lanes[lane] = _mm_xor_si128(Fold(lanes[lane], by512), Load(data + at + 16 * lane));
    }
  }
  __m128i folded = _mm_xor_si128(
      _mm_xor_si128(Fold(lanes[0], Multipliers(kFold384)), Fold(lanes[1], Multipliers(kFold256))),
      _mm_xor_si128(Fold(lanes[2], Multipliers(kFold128)), lanes[3]));
  const __m128i by128 = Multipliers(kFold128);
  for (; size - at >= 16; at += 16) folded = _mm_xor_si128(Fold(folded, by128), Load(data + at));
  std::array<char, 16> last;
  _mm_storeu_si128(reinterpret_cast<__m128i*>(last.data()), folded);
  // The folded block's remainder from a register started at zero (0xFFFFFFFF before inversion),
  // then the tail from there.
  const std::uint32_t through_last = ZlibCrc32(0xFFFFFFFFu, last.data(), last.size());
  return ZlibCrc32(through_last, data + at, size - at);
}

bool CanFold() {
  static const bool supported = __builtin_cpu_supports("pclmul") != 0;
  return supported;
}

#endif

}  // namespace

std::uint32_t Crc32Update(std::uint32_t crc, std::string_view bytes) {
#if defined(__x86_64__)
  // Below a few blocks the table is as fast and the fold not worth setting up.
  if (bytes.size() >= 256 && CanFold()) return FoldedCrc32(crc, bytes.data(), bytes.size());
#endif
  return ZlibCrc32(crc, bytes.data(), bytes.size());
}

}  // namespace hilrig::mcap
