#include "host/mcap/crc32.h"

#include <zlib.h>

namespace hilrig::mcap {

std::uint32_t Crc32Update(std::uint32_t crc, std::string_view bytes) {
  return static_cast<std::uint32_t>(
      crc32_z(crc, reinterpret_cast<const Bytef*>(bytes.data()), bytes.size()));
}

}  // namespace hilrig::mcap
