// What the on-disk caches (reference traces, tabulated field maps, calibrations) share: the 64-bit
// FNV-1a hash their keys are made with, protobuf messages as deterministic bytes for those keys,
// and whole-file reads and atomic writes. An entry is written to a name
// of this process's own and renamed into place, so a crash or Ctrl-C never leaves half an entry
// and two runs storing one key at once cannot interleave; a reader sees a whole entry or none.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "rig/result.h"

namespace google::protobuf {
class Message;
}

namespace hilrig::host {

class Fnv1a64 {
 public:
  void Add(const void* data, std::size_t size);
  // Length first, so that ("ab", "c") and ("a", "bc") differ.
  void Add(const std::string& text);
  std::string Hex() const;  // 16 hex digits

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

// The message's bytes, the same for equal messages (map order fixed).
std::string DeterministicBytes(const google::protobuf::Message& message);

// The whole file, or nothing when it cannot be opened.
std::optional<std::string> ReadWholeFile(const std::string& path);

// Creates `directory` if needed and puts `bytes` at `path` (inside it) atomically.
rig::Result<void> WriteFileAtomically(const std::string& directory, const std::string& path,
                                      const std::string& bytes);

}  // namespace hilrig::host
