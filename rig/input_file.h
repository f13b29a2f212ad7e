// A file read as a stream, a line at a time (a trace, a sweep shard's rows), trusted no further
// than rig/file_io.h trusts a whole file: only a regular file is opened (a FIFO or a device is
// refused, and the open never blocks), and lines are read with a cap (rig/bounded_line.h), so
// neither a file that never ends nor one without newlines can hang the reader or fill its memory.
#pragma once

#include <cstddef>
#include <istream>
#include <memory>
#include <streambuf>
#include <string>
#include <vector>

#include "rig/bounded_line.h"
#include "rig/result.h"

namespace hilrig::rig {

// A read buffer over a descriptor it owns; the first failed read is kept (errno).
class FdReadBuf final : public std::streambuf {
 public:
  FdReadBuf(int fd, std::size_t buffer_bytes);
  ~FdReadBuf() override;
  FdReadBuf(const FdReadBuf&) = delete;
  FdReadBuf& operator=(const FdReadBuf&) = delete;

  int error_number() const { return error_number_; }

 protected:
  int_type underflow() override;

 private:
  int fd_;
  std::vector<char> buffer_;
  int error_number_ = 0;
};

class InputFile {
 public:
  // Opens the regular file at `path` (OpenRegularFileForReading). Fails, naming the path, when it
  // cannot be opened or is not a regular file.
  static Result<std::unique_ptr<InputFile>> Open(const std::string& path,
                                                 std::size_t buffer_bytes = std::size_t{1} << 16);
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  const std::string& path() const { return path_; }
  std::istream& stream() { return stream_; }
  // The next line, at most `max_bytes` of it (ReadBoundedLine). A read error reads kReadError.
  LineRead ReadLine(std::size_t max_bytes, std::string& line);
  // "cannot read PATH: <reason>" after a kReadError.
  Error ReadError() const;

 private:
  InputFile(std::string path, int fd, std::size_t buffer_bytes);

  std::string path_;
  FdReadBuf buffer_;
  std::istream stream_;
};

}  // namespace hilrig::rig
