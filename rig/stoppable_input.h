// Line input from a file descriptor (a command's standard input) that a stop request ends within a
// fraction of a second. A std::getline on std::cin blocked on a pipe or a terminal does not return
// when Ctrl-C or SIGTERM arrives; this buffer waits in poll(2) with a short timeout and looks at
// the stop flag each time it wakes up. It hands out whole lines only: the start of a line still
// being written when the stop came is dropped rather than read as a shorter line, while at the
// end of the input a last line without its newline is read as usual.
#pragma once

#include <atomic>
#include <streambuf>
#include <string>

namespace hilrig::rig {

class StoppableLineBuf final : public std::streambuf {
 public:
  // Reads `fd` (not owned). `stop_requested` may be null.
  StoppableLineBuf(int fd, const std::atomic<bool>* stop_requested, int wake_up_ms = 100);
  StoppableLineBuf(const StoppableLineBuf&) = delete;
  StoppableLineBuf& operator=(const StoppableLineBuf&) = delete;

  // The input ended because a stop was requested.
  bool stopped() const { return stopped_; }
  // 0, or the errno of the read that failed and ended the input.
  int error_number() const { return error_number_; }

 protected:
  int_type underflow() override;

 private:
  // Reads once more into pending_; false at the end of the input, a stop or an error.
  bool ReadMore();

  int fd_;
  const std::atomic<bool>* stop_requested_;
  int wake_up_ms_;
  std::string pending_;  // read, not yet a whole line
  std::string lines_;    // whole lines being handed out
  bool stopped_ = false;
  int error_number_ = 0;
};

}  // namespace hilrig::rig
