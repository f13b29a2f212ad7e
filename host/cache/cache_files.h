// What the on-disk caches (reference traces, tabulated field maps, calibrations) share: the 64-bit
// FNV-1a hash their keys are made with, protobuf messages as deterministic bytes for those keys,
// and the folder that holds the entries.
//
// An entry is a header and its content. The header holds the cache's magic, the format version,
// the content's length and the FNV-1a 64 of the content, checked on every read, and each cache
// checks the content as it would the file it stands for (a calibration has six finite nodes, a
// table fits its grid). FNV-1a is enough here: it guards against damage and careless edits (a cut
// file, a changed byte: any change within one byte always changes it), not against someone who can
// write the cache folder, who could as well write a whole new entry with its checksum. An entry
// that fails a check is a miss, said on the notes stream, and is made and stored again.
//
// An entry is written to a random name beside it and renamed into place, so a crash or Ctrl-C
// never leaves half an entry and two runs storing one key at once cannot interleave; a reader sees
// a whole entry or none. Reading never blocks and never throws: a folder, FIFO or device at an
// entry's path is a miss. A long entry can also be written as it is made and read a block at a
// time (host/cache/cache_entry.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "host/cache/cache_entry.h"
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
  std::uint64_t value() const { return hash_; }
  std::string Hex() const;  // 16 hex digits

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

// The message's bytes, the same for equal messages (map order fixed).
std::string DeterministicBytes(const google::protobuf::Message& message);

// One cache's folder: an entry per key, named <key><extension>, and at most `max_entries` of them.
// Every key carries the executable's identity, so each rebuild starts a new set and the old ones
// are never read again: without a bound the folders grew by megabytes per build. A store beyond
// the bound removes the entries used least recently (a load marks its entry used). Only the
// cache's own files are ever removed: names of the entry form whose first bytes are the cache's
// magic, and temporary files of such names that a writer left an hour before the store (a writer
// that crashed; a live one writes its few hundred KB in milliseconds). A folder may hold other
// files of the extension: they are neither removed nor counted.
class CacheFolder {
 public:
  // `notes` (may be null) hears of entries that were there but could not be used.
  CacheFolder(std::string directory, const CacheFormat& format, std::ostream* notes);

  std::string PathOf(const std::string& key) const;

  // The content of the entry under `key` as `parse` reads it (parse: content -> rig::Result<T>).
  // Nothing when the entry is absent, or when it is there but cannot be used: not a regular file,
  // larger than the format's bound, a header or checksum that does not match, or content `parse`
  // refuses; those are said on the notes stream. A use marks the entry used.
  template <typename Parse>
  auto Load(const std::string& key, const Parse& parse) const
      -> std::optional<std::decay_t<decltype(parse(std::string()).value())>>;

  // Creates the folder if needed, puts the entry in place (header and `content`), and trims the
  // folder to max_entries.
  rig::Result<void> Store(const std::string& key, std::string_view content) const;

  // The entry under `key` open for reading, its header and checksum checked. Nothing when it is
  // absent; an error naming the path and the cause when it is there but cannot be used (as Load).
  rig::Result<std::optional<CacheEntryReader>> Open(const std::string& key) const;
  // Creates the folder if needed and starts the entry under `key` as a temporary file beside it.
  rig::Result<CacheEntryWriter> Begin(const std::string& key) const;
  // Puts a finished entry of Begin in place and trims the folder; refused past the format's bound.
  rig::Result<void> Commit(CacheEntryWriter& writer) const;

  // Says on the notes stream why an entry that was there is not used.
  void SayUnused(const rig::Error& why) const;
  // Marks the entry at `path` used now (trimming removes the least recently used).
  static void MarkUsed(const std::string& path);

  const std::string& directory() const { return directory_; }
  std::ostream* notes() const { return notes_; }

 private:
  // The content of the entry at `path`: nothing when there is none, an error naming the path and
  // the cause when it cannot be used.
  rig::Result<std::optional<std::string>> ReadContent(const std::string& path) const;
  // Removes the cache's own entries past the bound and its writers' old temporary files;
  // `fresh_path` is the entry just written, whose time stands for now.
  void Trim(const std::string& fresh_path) const;

  std::string directory_;
  CacheFormat format_;
  std::ostream* notes_;
};

template <typename Parse>
auto CacheFolder::Load(const std::string& key, const Parse& parse) const
    -> std::optional<std::decay_t<decltype(parse(std::string()).value())>> {
  const std::string path = PathOf(key);
  auto content = ReadContent(path);
  if (!content) {
    SayUnused(content.error());
    return std::nullopt;
  }
  if (!content.value()) return std::nullopt;
  auto parsed = parse(*content.value());
  if (!parsed) {
    SayUnused(rig::MakeError(path + ": " + parsed.error().message));
    return std::nullopt;
  }
  MarkUsed(path);
  return std::move(parsed).value();
}

// Tells `notes` (if any) that `what` could not be stored: a later run makes it again.
void SayIfNotKept(const rig::Result<void>& stored, const std::string& what, std::ostream* notes);

}  // namespace hilrig::host
