#include "host/cache/cache_entry.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "host/cache/cache_files.h"
#include "rig/file_io.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMagicBytes = 8;

void AppendWord(std::string& bytes, std::uint64_t word) {
  bytes.append(reinterpret_cast<const char*>(&word), sizeof(word));
}

std::uint64_t WordAt(std::string_view bytes, std::size_t at) {
  std::uint64_t word;
  std::memcpy(&word, bytes.data() + at, sizeof(word));
  return word;
}

// The blocks a long entry is read and checked in.
constexpr std::size_t kBlockBytes = std::size_t{1} << 16;

// Reads exactly `size` bytes at `offset`; false with errno set (0: the file ended first).
bool ReadFully(int fd, std::uint64_t offset, void* data, std::size_t size) {
  auto* at = static_cast<char*>(data);
  while (size > 0) {
    const ssize_t got = ::pread(fd, at, size, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      if (got == 0) errno = 0;
      return false;
    }
    at += got;
    offset += static_cast<std::uint64_t>(got);
    size -= static_cast<std::size_t>(got);
  }
  return true;
}

rig::Error ReadError(const std::string& path, int error_number) {
  return rig::MakeError("cannot read " + path + ": " +
                        (error_number == 0 ? std::string("shorter than its header says")
                                           : std::string(std::strerror(error_number))));
}

// The FNV-1a 64 of `size` bytes of the file at `offset`, read a block at a time.
rig::Result<std::uint64_t> ChecksumOfFile(int fd, const std::string& path, std::uint64_t offset,
                                          std::uint64_t size) {
  Fnv1a64 hash;
  std::vector<char> block(kBlockBytes);
  while (size > 0) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(size, kBlockBytes));
    if (!ReadFully(fd, offset, block.data(), n)) return ReadError(path, errno);
    hash.Add(block.data(), n);
    offset += n;
    size -= n;
  }
  return hash.value();
}

}  // namespace

std::string EntryHeader(const CacheFormat& format, std::uint64_t content_bytes,
                        std::uint64_t checksum) {
  std::string bytes(format.magic);
  AppendWord(bytes, format.version);
  AppendWord(bytes, content_bytes);
  AppendWord(bytes, checksum);
  return bytes;
}

rig::Result<std::uint64_t> PromisedChecksum(const CacheFormat& format, std::string_view header,
                                            std::uint64_t file_bytes) {
  if (header.size() < kEntryHeaderBytes || file_bytes < kEntryHeaderBytes ||
      header.substr(0, kMagicBytes) != format.magic) {
    return rig::MakeError("not an entry of this cache");
  }
  if (WordAt(header, kMagicBytes) != format.version) {
    return rig::MakeError("written in another format version");
  }
  if (WordAt(header, kMagicBytes + 8) != file_bytes - kEntryHeaderBytes) {
    return rig::MakeError("the content is not as long as the header says (cut or padded)");
  }
  return WordAt(header, kMagicBytes + 16);
}

rig::Error ChecksumMismatch() { return rig::MakeError("the checksum does not match the content"); }

rig::Result<CacheEntryReader> CacheEntryReader::Checked(int fd, std::string path,
                                                        std::uint64_t file_bytes,
                                                        const CacheFormat& format) {
  CacheEntryReader reader(fd, std::move(path), 0);
  const auto fail = [&reader](const rig::Error& why) {
    return rig::MakeError(reader.path_ + ": " + why.message);
  };
  std::string header(kEntryHeaderBytes, '\0');
  if (file_bytes < kEntryHeaderBytes || !ReadFully(fd, 0, header.data(), kEntryHeaderBytes)) {
    header.clear();
  }
  const auto promised = PromisedChecksum(format, header, file_bytes);
  if (!promised) return fail(promised.error());
  const std::uint64_t content_bytes = file_bytes - kEntryHeaderBytes;
  const auto checksum = ChecksumOfFile(fd, reader.path_, kEntryHeaderBytes, content_bytes);
  if (!checksum) return checksum.error();
  if (checksum.value() != promised.value()) return fail(ChecksumMismatch());
  reader.content_bytes_ = content_bytes;
  return reader;
}

CacheEntryReader::CacheEntryReader(CacheEntryReader&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      path_(std::move(other.path_)),
      content_bytes_(other.content_bytes_) {}

CacheEntryReader& CacheEntryReader::operator=(CacheEntryReader&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
    content_bytes_ = other.content_bytes_;
  }
  return *this;
}

CacheEntryReader::~CacheEntryReader() {
  if (fd_ >= 0) ::close(fd_);
}

rig::Result<void> CacheEntryReader::ReadAt(std::uint64_t offset, void* data,
                                           std::size_t size) const {
  if (offset > content_bytes_ || size > content_bytes_ - offset) return ReadError(path_, 0);
  if (!ReadFully(fd_, kEntryHeaderBytes + offset, data, size)) return ReadError(path_, errno);
  return {};
}

CacheEntryWriter::CacheEntryWriter(int fd, std::string temporary_path, std::string entry_path,
                                   const CacheFormat& format)
    : fd_(fd),
      temporary_path_(std::move(temporary_path)),
      entry_path_(std::move(entry_path)),
      format_(format) {
  buffer_.reserve(kBlockBytes * 4);
  buffer_.resize(kEntryHeaderBytes);  // the header's place, written by Finish
}

rig::Result<CacheEntryWriter> CacheEntryWriter::Unnamed(const CacheFormat& format) {
  std::error_code error;
  const fs::path folder = fs::temp_directory_path(error);
  if (error) return rig::MakeError("cannot make a temporary file: " + error.message());
  const int fd = ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd < 0) {
    return rig::MakeError("cannot make a temporary file in " + folder.string() + ": " +
                          std::strerror(errno));
  }
  return CacheEntryWriter(fd, "", "a temporary file in " + folder.string(), format);
}

CacheEntryWriter::CacheEntryWriter(CacheEntryWriter&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      temporary_path_(std::exchange(other.temporary_path_, std::string())),
      entry_path_(std::move(other.entry_path_)),
      format_(other.format_),
      buffer_(std::move(other.buffer_)),
      content_bytes_(other.content_bytes_),
      error_number_(other.error_number_),
      finished_(other.finished_) {}

CacheEntryWriter::~CacheEntryWriter() {
  if (fd_ >= 0) ::close(fd_);
  if (!temporary_path_.empty()) ::unlink(temporary_path_.c_str());
}

std::string CacheEntryWriter::Name() const { return entry_path_; }

bool CacheEntryWriter::Flush() {
  const char* at = buffer_.data();
  std::size_t size = buffer_.size();
  while (error_number_ == 0 && size > 0) {
    const ssize_t written = ::write(fd_, at, size);
    if (written < 0 && errno == EINTR) continue;
    if (written < 0) error_number_ = errno;
    if (written <= 0) break;
    at += written;
    size -= static_cast<std::size_t>(written);
  }
  if (error_number_ == 0 && size > 0) error_number_ = EIO;
  buffer_.clear();
  return error_number_ == 0;
}

void CacheEntryWriter::Append(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const char*>(data);
  buffer_.insert(buffer_.end(), bytes, bytes + size);
  content_bytes_ += size;
  if (buffer_.size() >= kBlockBytes * 4) Flush();
}

rig::Result<void> CacheEntryWriter::Finish(std::string_view head) {
  if (!Flush()) return rig::WriteError(Name(), error_number_);
  if (head.size() > content_bytes_) {
    return rig::MakeError("cannot write " + Name() + ": its head is longer than its content");
  }
  const auto settle = [this](std::uint64_t offset, std::string_view bytes) {
    while (!bytes.empty()) {
      const ssize_t written = ::pwrite(fd_, bytes.data(), bytes.size(), static_cast<off_t>(offset));
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) return false;
      bytes.remove_prefix(static_cast<std::size_t>(written));
      offset += static_cast<std::uint64_t>(written);
    }
    return true;
  };
  if (!settle(kEntryHeaderBytes, head)) return rig::WriteError(Name(), errno);
  const auto checksum = ChecksumOfFile(fd_, Name(), kEntryHeaderBytes, content_bytes_);
  if (!checksum) return checksum.error();
  if (!settle(0, EntryHeader(format_, content_bytes_, checksum.value())))
    return rig::WriteError(Name(), errno);
  finished_ = true;
  return {};
}

rig::Result<CacheEntryReader> CacheEntryWriter::Reader() const {
  if (!finished_) return rig::MakeError("cannot read " + Name() + ": it is not finished");
  const int fd = ::dup(fd_);
  if (fd < 0) return ReadError(Name(), errno);
  ::fcntl(fd, F_SETFD, FD_CLOEXEC);
  return CacheEntryReader::Checked(fd, Name(), kEntryHeaderBytes + content_bytes_, format_);
}

}  // namespace hilrig::host
