#include "rig/os_random.h"

#include <sys/random.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace hilrig::rig {

Result<void> FillWithOsRandomBytes(std::span<std::uint8_t> out) {
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t got = ::getrandom(out.data() + done, out.size() - done, 0);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) return MakeError(std::string("getrandom: ") + std::strerror(errno));
    done += static_cast<std::size_t>(got);
  }
  return {};
}

}  // namespace hilrig::rig
