// What the on-disk caches (reference traces, tabulated field maps, calibrations) share: the 64-bit
// FNV-1a hash their keys are made with, protobuf messages as deterministic bytes for those keys,
// and the folder that holds the entries. An entry is written to a name of this process's own and
// renamed into place, so a crash or Ctrl-C never leaves half an entry and two runs storing one key
// at once cannot interleave; a reader sees a whole entry or none.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <ostream>
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

// One cache's folder: an entry per key, named <key><extension>, read whole, written atomically,
// and at most `max_entries` of them. Every key carries the executable's identity, so each rebuild
// starts a new set and the old ones are never read again: without a bound the folders grew by
// megabytes per build. A store beyond the bound removes the entries used least recently (a load
// marks its entry used).
class CacheFolder {
 public:
  CacheFolder(std::string directory, std::string extension, std::size_t max_entries);

  std::string PathOf(const std::string& key) const;
  // The entry's bytes, or nothing when it is absent or unreadable.
  std::optional<std::string> Load(const std::string& key) const;
  // Creates the folder if needed, puts the entry in place, and trims the folder to max_entries.
  rig::Result<void> Store(const std::string& key, const std::string& bytes) const;

  const std::string& directory() const { return directory_; }

 private:
  void RemoveLeastRecentlyUsed() const;

  std::string directory_;
  std::string extension_;
  std::size_t max_entries_;
};

// Tells `notes` (if any) that `what` could not be stored: a later run makes it again.
void SayIfNotKept(const rig::Result<void>& stored, const std::string& what, std::ostream* notes);

}  // namespace hilrig::host
