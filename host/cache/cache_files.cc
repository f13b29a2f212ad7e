#include "host/cache/cache_files.h"

#include <fcntl.h>
#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <google/protobuf/message.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

#include "rig/file_io.h"

namespace hilrig::host {

void Fnv1a64::Add(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash_ ^= bytes[i];
    hash_ *= 0x100000001b3ULL;
  }
}

void Fnv1a64::Add(const std::string& text) {
  const std::uint64_t size = text.size();
  Add(&size, sizeof(size));
  Add(text.data(), text.size());
}

std::string Fnv1a64::Hex() const {
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash_));
  return text;
}

std::string DeterministicBytes(const google::protobuf::Message& message) {
  std::string bytes;
  google::protobuf::io::StringOutputStream stream(&bytes);
  google::protobuf::io::CodedOutputStream coded(&stream);
  coded.SetSerializationDeterministic(true);
  message.SerializeToCodedStream(&coded);
  coded.Trim();
  return bytes;
}

namespace {

namespace fs = std::filesystem;

// A temporary file a crashed writer left is removed once it is this much older than a fresh entry.
constexpr auto kAbandonedTemporaryAge = std::chrono::hours(1);

std::uint64_t Checksum(std::string_view content) {
  Fnv1a64 hash;
  hash.Add(content.data(), content.size());
  return hash.value();
}

std::string EntryBytes(const CacheFormat& format, std::string_view content) {
  std::string bytes = EntryHeader(format, content.size(), Checksum(content));
  bytes.append(content);
  return bytes;
}

// The content of an entry's bytes, or why they are not a whole entry of `format`.
rig::Result<std::string> EntryContent(const CacheFormat& format, std::string bytes) {
  const auto promised = PromisedChecksum(format, bytes, bytes.size());
  if (!promised) return promised.error();
  if (promised.value() != Checksum(std::string_view(bytes).substr(kEntryHeaderBytes))) {
    return ChecksumMismatch();
  }
  bytes.erase(0, kEntryHeaderBytes);
  return bytes;
}

// Refuses an entry of `bytes` (header included) that the cache would not read back.
rig::Result<void> WithinBound(const CacheFormat& format, const std::string& path,
                              std::uint64_t bytes) {
  if (bytes <= format.max_entry_bytes) return {};
  return rig::MakeError("cannot write " + path + ": " + std::to_string(bytes) +
                        " bytes, more than the cache reads back (" +
                        std::to_string(format.max_entry_bytes) + ")");
}

// Whether a file's first bytes are those of this cache's entries, now or before the header.
bool OpensAsOwnEntry(const std::string& head, const CacheFormat& format) {
  return head == format.magic || (!format.legacy_magic.empty() && head == format.legacy_magic);
}

bool IsHexKey(std::string_view text) {
  return text.size() == 16 && std::all_of(text.begin(), text.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

// <16 hex digits><extension>: the names this cache gives its entries.
bool IsEntryName(std::string_view name, std::string_view extension) {
  return name.size() == 16 + extension.size() && name.substr(16) == extension &&
         IsHexKey(name.substr(0, 16));
}

// <entry name>.tmp-<16 hex digits>: rig::TemporaryNameBeside of an entry's path.
bool IsTemporaryName(std::string_view name, std::string_view extension) {
  constexpr std::string_view kTmp = ".tmp-";
  const std::size_t entry = 16 + extension.size();
  return name.size() == entry + kTmp.size() + 16 && IsEntryName(name.substr(0, entry), extension) &&
         name.substr(entry, kTmp.size()) == kTmp && IsHexKey(name.substr(entry + kTmp.size()));
}

}  // namespace

CacheFolder::CacheFolder(std::string directory, const CacheFormat& format, std::ostream* notes)
    : directory_(std::move(directory)), format_(format), notes_(notes) {
  format_.max_entries = std::max<std::size_t>(1, format_.max_entries);
}

std::string CacheFolder::PathOf(const std::string& key) const {
  return (fs::path(directory_) / (key + std::string(format_.extension))).string();
}

rig::Result<std::optional<std::string>> CacheFolder::ReadContent(const std::string& path) const {
  std::error_code error;
  if (fs::symlink_status(path, error).type() == fs::file_type::not_found) {
    return std::optional<std::string>();
  }
  auto bytes = rig::ReadRegularFile(path, format_.max_entry_bytes);
  if (!bytes) return bytes.error();
  auto content = EntryContent(format_, std::move(bytes).value());
  if (!content) return rig::MakeError(path + ": " + content.error().message);
  return std::optional<std::string>(std::move(content).value());
}

void CacheFolder::SayUnused(const rig::Error& why) const {
  if (notes_ != nullptr) {
    *notes_ << "hilrig: " << why.message << "; the cache entry is not used and is made again\n";
  }
}

void CacheFolder::MarkUsed(const std::string& path) {
  // The modification time is what trimming orders by; the kernel stamps it (no clock is read
  // here), and a failure only makes the entry look older.
  ::utimensat(AT_FDCWD, path.c_str(), nullptr, 0);
}

void CacheFolder::Trim(const std::string& fresh_path) const {
  std::error_code error;
  const fs::file_time_type now = fs::last_write_time(fresh_path, error);
  if (error) return;
  std::vector<std::pair<fs::file_time_type, fs::path>> entries;
  fs::directory_iterator next(directory_, error);
  for (; !error && next != fs::directory_iterator(); next.increment(error)) {
    const fs::path& path = next->path();
    const std::string name = path.filename().string();
    std::error_code file_error;
    if (next->symlink_status(file_error).type() != fs::file_type::regular) continue;
    const fs::file_time_type used = next->last_write_time(file_error);
    if (file_error) continue;
    if (IsTemporaryName(name, format_.extension)) {
      if (used < now - kAbandonedTemporaryAge) fs::remove(path, file_error);
      continue;
    }
    if (!IsEntryName(name, format_.extension)) continue;
    const auto head = rig::ReadRegularFileHead(path.string(), format_.magic.size());
    if (head && OpensAsOwnEntry(head.value(), format_)) entries.emplace_back(used, path);
  }
  if (entries.size() <= format_.max_entries) return;
  std::sort(entries.begin(), entries.end());
  for (std::size_t i = 0; i < entries.size() - format_.max_entries; ++i) {
    fs::remove(entries[i].second, error);  // another process may have removed it first
  }
}

rig::Result<void> CacheFolder::Store(const std::string& key, std::string_view content) const {
  const std::string path = PathOf(key);
  if (auto bounded = WithinBound(format_, path, kEntryHeaderBytes + content.size()); !bounded) {
    return bounded;
  }
  std::error_code error;
  fs::create_directories(directory_, error);
  if (error) return rig::MakeError("cannot create " + directory_ + ": " + error.message());
  if (auto written = rig::WriteFileAtomically(path, EntryBytes(format_, content)); !written) {
    return written;
  }
  Trim(path);
  return {};
}

rig::Result<std::optional<CacheEntryReader>> CacheFolder::Open(const std::string& key) const {
  const std::string path = PathOf(key);
  std::error_code error;
  if (fs::symlink_status(path, error).type() == fs::file_type::not_found) {
    return std::optional<CacheEntryReader>();
  }
  // The same checks and words as a whole read (a folder, a FIFO: never blocking on it).
  if (auto head = rig::ReadRegularFileHead(path, kEntryHeaderBytes); !head) return head.error();
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) return rig::MakeError("cannot read " + path + ": " + std::strerror(errno));
  struct stat status {};
  if (::fstat(fd, &status) != 0 || !S_ISREG(status.st_mode)) {
    ::close(fd);
    return rig::MakeError("cannot read " + path + ": not a regular file");
  }
  const auto file_bytes = static_cast<std::uint64_t>(status.st_size);
  if (file_bytes > format_.max_entry_bytes) {
    ::close(fd);
    return rig::MakeError("cannot read " + path + ": larger than " +
                          std::to_string(format_.max_entry_bytes) + " bytes");
  }
  auto reader = CacheEntryReader::Checked(fd, path, file_bytes, format_);
  if (!reader) return reader.error();
  return std::optional<CacheEntryReader>(std::move(reader).value());
}

rig::Result<CacheEntryWriter> CacheFolder::Begin(const std::string& key) const {
  const std::string path = PathOf(key);
  std::error_code error;
  fs::create_directories(directory_, error);
  if (error) return rig::MakeError("cannot create " + directory_ + ": " + error.message());
  std::string temporary = rig::TemporaryNameBeside(path);
  const int fd =
      ::open(temporary.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) return rig::WriteError(path, errno);
  return CacheEntryWriter(fd, std::move(temporary), path, format_);
}

rig::Result<void> CacheFolder::Commit(CacheEntryWriter& writer) const {
  const std::string& path = writer.entry_path_;
  if (!writer.finished_ || writer.temporary_path_.empty()) {
    return rig::MakeError("cannot write " + path + ": the entry is not finished");
  }
  if (auto bounded = WithinBound(format_, path, kEntryHeaderBytes + writer.content_bytes_);
      !bounded) {
    return bounded;
  }
  if (::rename(writer.temporary_path_.c_str(), path.c_str()) != 0) {
    return rig::WriteError(path, errno);  // the writer removes its temporary file
  }
  writer.temporary_path_.clear();
  Trim(path);
  return {};
}

void SayIfNotKept(const rig::Result<void>& stored, const std::string& what, std::ostream* notes) {
  if (!stored && notes != nullptr) {
    *notes << "hilrig: the " << what << " is not kept for later runs: " << stored.error().message
           << "\n";
  }
}

}  // namespace hilrig::host
