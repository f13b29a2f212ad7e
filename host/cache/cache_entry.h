// A cache entry's layout and its reading and writing a block at a time. An entry is a header (the
// cache's magic, the format version, the content's length and its FNV-1a 64) and its content. A
// long entry (a reference trace grows with the simulated duration) is written as it is made
// (CacheEntryWriter, to a temporary file that host/cache/cache_files.h's CacheFolder renames into
// place) and read a block at a time (CacheEntryReader, its checksum checked in a first pass over
// the file), so neither side holds it whole.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rig/result.h"

namespace hilrig::host {

// What tells one cache's entries from every other file in its folder, and its bounds.
struct CacheFormat {
  std::string_view extension;  // of the entry names: <16 hex digits><extension>
  std::string_view magic;      // 8 bytes, the first of every entry
  std::uint64_t version = 1;   // of the content's layout
  // What opened this cache's entries before they had a header: such files are still the cache's
  // own to trim, never read.
  std::string_view legacy_magic;
  std::size_t max_entries = 1;
  std::size_t max_entry_bytes = 0;  // header included; a larger file is not read
};

// The bytes before an entry's content: magic, format version, content length, FNV-1a 64 of the
// content (host byte order: the keys carry the executable's identity, so an entry is read only by
// the build that wrote it).
constexpr std::size_t kEntryHeaderBytes = 8 + 3 * sizeof(std::uint64_t);

std::string EntryHeader(const CacheFormat& format, std::uint64_t content_bytes,
                        std::uint64_t checksum);
// The checksum an entry's header promises for its content, or why `header` (its first
// kEntryHeaderBytes, or fewer) is not that of an entry of `format` of `file_bytes` bytes.
rig::Result<std::uint64_t> PromisedChecksum(const CacheFormat& format, std::string_view header,
                                            std::uint64_t file_bytes);
rig::Error ChecksumMismatch();

class CacheFolder;

// An entry open for reading, its header and checksum checked: its content read a block at a time
// from the one open file (a rename over its path does not change what it reads).
class CacheEntryReader {
 public:
  CacheEntryReader(CacheEntryReader&& other) noexcept;
  CacheEntryReader& operator=(CacheEntryReader&& other) noexcept;
  ~CacheEntryReader();

  std::uint64_t content_bytes() const { return content_bytes_; }
  const std::string& path() const { return path_; }
  // Exactly `size` bytes of content from `offset`; fails, naming the file, when it cannot be read
  // or is shorter than that (cut since it was checked).
  rig::Result<void> ReadAt(std::uint64_t offset, void* data, std::size_t size) const;

 private:
  friend class CacheFolder;
  friend class CacheEntryWriter;
  // Checks the header and the checksum of the entry open at `fd` (taken: closed on failure) of
  // `file_bytes` bytes; `path` names it in errors.
  static rig::Result<CacheEntryReader> Checked(int fd, std::string path, std::uint64_t file_bytes,
                                               const CacheFormat& format);
  CacheEntryReader(int fd, std::string path, std::uint64_t content_bytes)
      : fd_(fd), path_(std::move(path)), content_bytes_(content_bytes) {}

  int fd_ = -1;
  std::string path_;
  std::uint64_t content_bytes_ = 0;
};

// An entry written as it is made: content appended in order through a buffer, then finished
// (header, checksum) and put in place by CacheFolder::Commit. Until then it is a temporary file
// that no reader takes for an entry, removed when the writer is dropped (a run that stopped short
// leaves nothing; one that was killed leaves a temporary file that a later store removes).
class CacheEntryWriter {
 public:
  // A writer with no entry path: an unnamed temporary file, for content a run needs read back
  // although no cache keeps it. Fails when no such file can be made.
  static rig::Result<CacheEntryWriter> Unnamed(const CacheFormat& format);

  CacheEntryWriter(CacheEntryWriter&& other) noexcept;
  CacheEntryWriter& operator=(CacheEntryWriter&& other) = delete;
  ~CacheEntryWriter();

  // Appends to the content; the first failure is kept and reported by Finish.
  void Append(const void* data, std::size_t size);
  std::uint64_t content_bytes() const { return content_bytes_; }
  // Puts `head` over the content's first bytes (what is known only at the end: a count), then
  // the header with the checksum of the content read back; fails naming the file and the cause.
  rig::Result<void> Finish(std::string_view head);
  // The finished content for reading (checked as an entry is), from the file this writer made.
  rig::Result<CacheEntryReader> Reader() const;

 private:
  friend class CacheFolder;
  CacheEntryWriter(int fd, std::string temporary_path, std::string entry_path,
                   const CacheFormat& format);
  bool Flush();
  std::string Name() const;  // the entry it stands for, in errors

  int fd_ = -1;
  std::string temporary_path_;  // empty: unnamed, or renamed into place
  std::string entry_path_;
  CacheFormat format_;
  std::vector<char> buffer_;
  std::uint64_t content_bytes_ = 0;
  int error_number_ = 0;
  bool finished_ = false;
};

}  // namespace hilrig::host
