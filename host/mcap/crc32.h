// CRC-32 as zlib and the MCAP format compute it: the reflected polynomial 0xEDB88320, the register
// started at 0xFFFFFFFF and inverted at the end. Incremental: Crc32Update(Crc32Update(0, a), b)
// equals Crc32Update(0, a + b), so a writer can checksum a section as it streams it out.
// zlib's own crc32_z (several bytes a step, GB/s): a run's log checksums every byte twice, as
// records and as compressed chunks. Never allocates and never fails.
#pragma once

#include <cstdint>
#include <string_view>

namespace hilrig::mcap {

// The CRC of the bytes so far (`crc`, 0 before the first byte) extended by `bytes`.
std::uint32_t Crc32Update(std::uint32_t crc, std::string_view bytes);

inline std::uint32_t Crc32(std::string_view bytes) { return Crc32Update(0, bytes); }

}  // namespace hilrig::mcap
