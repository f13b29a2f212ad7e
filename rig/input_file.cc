#include "rig/input_file.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "rig/file_io.h"

namespace hilrig::rig {

FdReadBuf::FdReadBuf(int fd, std::size_t buffer_bytes)
    : fd_(fd), buffer_(std::max<std::size_t>(buffer_bytes, 1)) {
  setg(buffer_.data(), buffer_.data(), buffer_.data());
}

FdReadBuf::~FdReadBuf() {
  if (fd_ >= 0) ::close(fd_);
}

FdReadBuf::int_type FdReadBuf::underflow() {
  if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
  if (error_number_ != 0) return traits_type::eof();
  for (;;) {
    const ssize_t got = ::read(fd_, buffer_.data(), buffer_.size());
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      error_number_ = errno;
      // To the stream a failed read is the end; InputFile::ReadLine tells the two apart.
      return traits_type::eof();
    }
    if (got == 0) return traits_type::eof();
    setg(buffer_.data(), buffer_.data(), buffer_.data() + got);
    return traits_type::to_int_type(*gptr());
  }
}

Result<std::unique_ptr<InputFile>> InputFile::Open(const std::string& path,
                                                   std::size_t buffer_bytes) {
  auto fd = OpenRegularFileForReading(path);
  if (!fd) return fd.error();
  return std::unique_ptr<InputFile>(new InputFile(path, fd.value(), buffer_bytes));
}

InputFile::InputFile(std::string path, int fd, std::size_t buffer_bytes)
    : path_(std::move(path)), buffer_(fd, buffer_bytes), stream_(&buffer_) {}

LineRead InputFile::ReadLine(std::size_t max_bytes, std::string& line) {
  const LineRead read = ReadBoundedLine(stream_, max_bytes, line);
  return buffer_.error_number() != 0 ? LineRead::kReadError : read;
}

Error InputFile::ReadError() const {
  return MakeError("cannot read " + path_ + ": " +
                   std::strerror(buffer_.error_number() != 0 ? buffer_.error_number() : EIO));
}

}  // namespace hilrig::rig
