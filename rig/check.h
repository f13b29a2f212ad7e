// HILRIG_CHECK guards invariants whose violation means the program itself is wrong (not the input).
// Such bugs must stop the run at the spot, loudly, instead of producing a plausible-looking but
// corrupt trace; recoverable problems go through Result<T> instead.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string_view>

// The file a check names: its name alone (GCC's __FILE_NAME__), not __FILE__, which holds the
// path the compiler was given. That path is absolute in one build and relative in another (the
// compiler cache rewrites it so that clones share objects), and the programs must be the same
// bytes however they were built.
#define HILRIG_SOURCE_FILE __FILE_NAME__

namespace hilrig::rig::check_internal {

[[noreturn]] inline void Fail(std::string_view condition, std::string_view message,
                              const char* file, int line) {
  std::fprintf(stderr, "%s:%d: HILRIG_CHECK(%.*s) failed: %.*s\n", file, line,
               static_cast<int>(condition.size()), condition.data(),
               static_cast<int>(message.size()), message.data());
  std::fflush(stderr);
  std::abort();
}

}  // namespace hilrig::rig::check_internal

#define HILRIG_CHECK(cond, msg)                                                        \
  do {                                                                                 \
    if (!(cond)) [[unlikely]] {                                                        \
      ::hilrig::rig::check_internal::Fail(#cond, (msg), HILRIG_SOURCE_FILE, __LINE__); \
    }                                                                                  \
  } while (false)
