// Files the rig reads and writes, trusted no further than they must be. Inputs (scenario specs,
// calibration files, cache entries) are read only when they are regular files, under a size cap,
// without ever blocking on a FIFO or a device. Outputs are created without following a symlink
// planted at their path, every write is checked, and a failure is an error that names the file
// and the system's reason (ENOSPC reads "No space left on device"), never a silent loss. Whole
// files are written under an unpredictable temporary name beside the target and renamed over it,
// so a reader sees the old file or the new one, never a cut one.
#pragma once

#include <cstddef>
#include <memory>
#include <ostream>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

#include "rig/result.h"

namespace hilrig::rig {

// Reads the regular file at `path` whole. Fails, naming the path, when it cannot be opened, is not
// a regular file (a folder, a FIFO, a device: checked on the opened descriptor, which is opened
// non-blocking so a FIFO without a writer cannot hang the call), or holds more than `max_bytes`
// (read with that limit, so a file that grows while it is read cannot exhaust memory either).
// The error never quotes the file's content.
Result<std::string> ReadRegularFile(const std::string& path, std::size_t max_bytes);

// The first `max_bytes` bytes of the regular file at `path` (all of it when shorter), with
// ReadRegularFile's checks: for telling what a file is by its header without reading it whole.
Result<std::string> ReadRegularFileHead(const std::string& path, std::size_t max_bytes);

// Opens the regular file at `path` for reading, as ReadRegularFile checks it (a FIFO, a device or
// a folder is refused without blocking), and returns its descriptor in blocking mode,
// close-on-exec; the caller closes it. The error names the path and what it is instead.
Result<int> OpenRegularFileForReading(const std::string& path);

// A random name for a temporary file beside `path`: "<path>.tmp-<16 hex digits>" from the
// kernel's random source, so another local user cannot guess it and plant a link there first.
std::string TemporaryNameBeside(const std::string& path);

// Writes `content` to `path` whole or not at all: to TemporaryNameBeside(path), created
// exclusively (O_EXCL, never following a link), every write checked, then renamed over `path`
// (rename replaces a symlink at `path` itself, never its target). On failure the temporary file
// is removed and the error names `path` and the cause.
Result<void> WriteFileAtomically(const std::string& path, std::string_view content);

// A stream buffer over a file descriptor with a buffer of its own size, whose first failed write
// is kept (errno) rather than lost in a stream's badbit.
class FdStreamBuf final : public std::streambuf {
 public:
  FdStreamBuf(int fd, std::size_t buffer_bytes);
  ~FdStreamBuf() override;
  FdStreamBuf(const FdStreamBuf&) = delete;
  FdStreamBuf& operator=(const FdStreamBuf&) = delete;

  // 0 while every write went through; else the errno of the first one that did not.
  int error_number() const { return error_number_; }
  // Flushes and closes the descriptor; false if anything failed (see error_number()).
  bool Close();

 protected:
  int_type overflow(int_type ch) override;
  int sync() override;
  std::streamsize xsputn(const char* data, std::streamsize size) override;

 private:
  bool Drain();
  bool WriteAll(const char* data, std::size_t size);

  int fd_;
  std::vector<char> buffer_;
  int error_number_ = 0;
};

// A file written as a stream (a trace, a CAN log) from inside a run: created or truncated without
// following a symlink at its path (O_NOFOLLOW), refused when something other than a regular file
// is there (a FIFO would block the run until someone reads it, a device would swallow it; the
// open never blocks), buffered in `buffer_bytes` (a write system call
// costs tens of microseconds on a VM, and the stepping loop's wall time is the real-time factor).
class OutputFile {
 public:
  static Result<std::unique_ptr<OutputFile>> Create(const std::string& path,
                                                    std::size_t buffer_bytes = std::size_t{1}
                                                                               << 20);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::ostream& stream() { return stream_; }
  const std::string& path() const { return path_; }
  // Flushes and closes; the error names the file and the first failed write's cause.
  Result<void> Close();
  // Flushes what is buffered (e.g. so a killed run keeps what it wrote); errors as Close.
  Result<void> Flush();

 private:
  OutputFile(std::string path, int fd, std::size_t buffer_bytes);
  Result<void> Status() const;

  std::string path_;
  FdStreamBuf buffer_;
  std::ostream stream_;
  bool closed_ = false;
};

// "cannot write PATH: <strerror(error_number)>".
Error WriteError(const std::string& path, int error_number);

}  // namespace hilrig::rig
