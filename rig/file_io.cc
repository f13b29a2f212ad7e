#include "rig/file_io.h"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace hilrig::rig {
namespace {

std::string Reason(int error_number) { return std::strerror(error_number); }

Error OpenError(const std::string& path, int error_number) {
  if (error_number == ELOOP) {
    return MakeError("cannot write " + path + ": it is a symbolic link, which is not followed");
  }
  return WriteError(path, error_number);
}

// What kind of thing a non-regular file is, for the message.
const char* KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Closes on scope exit; the read path needs no close status.
struct ScopedFd {
  int fd;
  ~ScopedFd() {
    if (fd >= 0) ::close(fd);
  }
};

// Opens `path` for reading, never blocking (a FIFO without a writer), and checks that it is a
// regular file; its size, or an error that names the path.
Result<std::size_t> OpenRegularFile(const std::string& path, ScopedFd& file) {
  file.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (file.fd < 0) return MakeError("cannot read " + path + ": " + Reason(errno));
  struct stat status {};
  if (::fstat(file.fd, &status) != 0)
    return MakeError("cannot read " + path + ": " + Reason(errno));
  if (!S_ISREG(status.st_mode)) {
    return MakeError("cannot read " + path + ": " + KindOf(status.st_mode) +
                     ", not a regular file");
  }
  return static_cast<std::size_t>(status.st_size);
}

// Reads until the end of the file or `limit` bytes, whichever comes first; `expected_bytes` sizes
// the first buffer.
Result<std::string> ReadAtMost(const ScopedFd& file, const std::string& path, std::size_t limit,
                               std::size_t expected_bytes) {
  std::string bytes;
  bytes.resize(std::min(limit, expected_bytes));
  std::size_t used = 0;
  while (used < limit) {
    if (used == bytes.size()) bytes.resize(std::min(limit, used * 2 + 4096));
    const ssize_t got = ::read(file.fd, bytes.data() + used, bytes.size() - used);
    if (got < 0) {
      if (errno == EINTR) continue;
      return MakeError("cannot read " + path + ": " + Reason(errno));
    }
    if (got == 0) break;
    used += static_cast<std::size_t>(got);
  }
  bytes.resize(used);
  return bytes;
}

}  // namespace

Error WriteError(const std::string& path, int error_number) {
  return MakeError("cannot write " + path + ": " + Reason(error_number));
}

Result<int> OpenRegularFileForReading(const std::string& path) {
  ScopedFd file{-1};
  const auto size = OpenRegularFile(path, file);
  if (!size) return size.error();
  const int flags = ::fcntl(file.fd, F_GETFL);
  if (flags < 0 || ::fcntl(file.fd, F_SETFL, flags & ~O_NONBLOCK) != 0) {
    return MakeError("cannot read " + path + ": " + Reason(errno));
  }
  const int fd = file.fd;
  file.fd = -1;
  return fd;
}

Result<std::string> ReadRegularFile(const std::string& path, std::size_t max_bytes) {
  ScopedFd file{-1};
  const auto size = OpenRegularFile(path, file);
  if (!size) return size.error();
  const auto too_large = [&] {
    return MakeError("cannot read " + path + ": larger than " + std::to_string(max_bytes) +
                     " bytes");
  };
  if (size.value() > max_bytes) return too_large();
  // One byte past the cap, so that a file that grew since fstat is seen to be too large.
  auto bytes = ReadAtMost(file, path, max_bytes + 1, size.value() + 1);
  if (bytes && bytes.value().size() > max_bytes) return too_large();
  return bytes;
}

Result<std::string> ReadRegularFileHead(const std::string& path, std::size_t max_bytes) {
  ScopedFd file{-1};
  const auto size = OpenRegularFile(path, file);
  if (!size) return size.error();
  return ReadAtMost(file, path, max_bytes, std::min(max_bytes, size.value()));
}

std::string TemporaryNameBeside(const std::string& path) {
  unsigned long long random = 0;
  std::size_t got = 0;
  while (got < sizeof(random)) {
    const ssize_t n = ::getrandom(reinterpret_cast<char*>(&random) + got, sizeof(random) - got, 0);
    if (n > 0) got += static_cast<std::size_t>(n);
    // EINTR retries; the kernel's source does not fail otherwise once it is initialised.
  }
  char suffix[24];
  std::snprintf(suffix, sizeof(suffix), ".tmp-%016llx", random);
  return path + suffix;
}

Result<void> WriteFileAtomically(const std::string& path, std::string_view content) {
  const std::string temporary = TemporaryNameBeside(path);
  const int fd =
      ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) return WriteError(path, errno);
  FdStreamBuf out(fd, 0);
  out.sputn(content.data(), static_cast<std::streamsize>(content.size()));
  if (!out.Close()) {
    const int error_number = out.error_number();
    ::unlink(temporary.c_str());
    return WriteError(path, error_number);
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error_number = errno;
    ::unlink(temporary.c_str());
    return WriteError(path, error_number);
  }
  return {};
}

FdStreamBuf::FdStreamBuf(int fd, std::size_t buffer_bytes) : fd_(fd), buffer_(buffer_bytes) {
  if (!buffer_.empty()) setp(buffer_.data(), buffer_.data() + buffer_.size());
}

FdStreamBuf::~FdStreamBuf() { Close(); }

bool FdStreamBuf::WriteAll(const char* data, std::size_t size) {
  if (error_number_ != 0) return false;  // the first failure stands; nothing after it is written
  while (size > 0) {
    const ssize_t written = ::write(fd_, data, size);
    if (written < 0) {
      if (errno == EINTR) continue;
      error_number_ = errno;
      return false;
    }
    data += written;
    size -= static_cast<std::size_t>(written);
  }
  return true;
}

bool FdStreamBuf::Drain() {
  const bool written = WriteAll(pbase(), static_cast<std::size_t>(pptr() - pbase()));
  if (!buffer_.empty()) setp(buffer_.data(), buffer_.data() + buffer_.size());
  return written;
}

FdStreamBuf::int_type FdStreamBuf::overflow(int_type ch) {
  if (!Drain()) return traits_type::eof();
  if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
  const char c = traits_type::to_char_type(ch);
  if (buffer_.empty()) return WriteAll(&c, 1) ? ch : traits_type::eof();
  *pptr() = c;
  pbump(1);
  return ch;
}

int FdStreamBuf::sync() { return Drain() ? 0 : -1; }

std::streamsize FdStreamBuf::xsputn(const char* data, std::streamsize size) {
  if (size <= 0) return 0;
  const auto room = epptr() - pptr();
  if (size <= room) {
    std::memcpy(pptr(), data, static_cast<std::size_t>(size));
    pbump(static_cast<int>(size));
    return size;
  }
  // Larger than what is left: drain and write it straight through.
  if (!Drain() || !WriteAll(data, static_cast<std::size_t>(size))) return 0;
  return size;
}

bool FdStreamBuf::Close() {
  if (fd_ < 0) return error_number_ == 0;
  Drain();
  if (::close(fd_) != 0 && error_number_ == 0) error_number_ = errno;
  fd_ = -1;
  return error_number_ == 0;
}

Result<std::unique_ptr<OutputFile>> OutputFile::Create(const std::string& path,
                                                       std::size_t buffer_bytes) {
  // Non-blocking and without O_TRUNC until the descriptor is known to be a regular file: opening a
  // FIFO for writing blocks until a reader comes, and truncating is for files only.
  ScopedFd file{::open(path.c_str(),
                       O_WRONLY | O_CREAT | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK | O_NOCTTY, 0644)};
  if (file.fd < 0) {
    // ENXIO: a FIFO that nobody reads.
    if (errno == ENXIO) return MakeError("cannot write " + path + ": a FIFO, not a regular file");
    return OpenError(path, errno);
  }
  struct stat status {};
  if (::fstat(file.fd, &status) != 0) return WriteError(path, errno);
  if (!S_ISREG(status.st_mode)) {
    return MakeError("cannot write " + path + ": " + KindOf(status.st_mode) +
                     ", not a regular file");
  }
  const int flags = ::fcntl(file.fd, F_GETFL);
  if (flags < 0 || ::fcntl(file.fd, F_SETFL, flags & ~O_NONBLOCK) != 0 ||
      ::ftruncate(file.fd, 0) != 0) {
    return WriteError(path, errno);
  }
  const int fd = file.fd;
  file.fd = -1;
  return std::unique_ptr<OutputFile>(new OutputFile(path, fd, buffer_bytes));
}

OutputFile::OutputFile(std::string path, int fd, std::size_t buffer_bytes)
    : path_(std::move(path)), buffer_(fd, buffer_bytes), stream_(&buffer_) {}

OutputFile::~OutputFile() { buffer_.Close(); }

Result<void> OutputFile::Status() const {
  if (buffer_.error_number() != 0) return WriteError(path_, buffer_.error_number());
  if (!stream_) return MakeError("cannot write " + path_);
  return {};
}

Result<void> OutputFile::Flush() {
  if (!closed_) stream_.flush();
  return Status();
}

Result<void> OutputFile::Close() {
  if (!closed_) {
    stream_.flush();
    buffer_.Close();
    closed_ = true;
  }
  return Status();
}

}  // namespace hilrig::rig
