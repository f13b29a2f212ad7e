#include "rig/stoppable_input.h"

#include <poll.h>
#include <unistd.h>

#include <cerrno>

#include "rig/stop_request.h"

namespace hilrig::rig {
namespace {

// A line longer than this is handed out in pieces (std::getline joins them) rather than held
// whole: input without newlines must not grow the buffer without bound.
constexpr std::size_t kMaxHeldBytes = 64 * 1024;
constexpr std::size_t kReadChunkBytes = 4096;

}  // namespace

StoppableLineBuf::StoppableLineBuf(int fd, const std::atomic<bool>* stop_requested, int wake_up_ms)
    : fd_(fd), stop_requested_(stop_requested), wake_up_ms_(wake_up_ms) {}

bool StoppableLineBuf::ReadMore() {
  if (fd_ < 0) {  // poll(2) would skip it and wait for ever
    error_number_ = EBADF;
    return false;
  }
  char chunk[kReadChunkBytes];
  while (true) {
    if (StopRequested(stop_requested_)) {
      stopped_ = true;
      return false;
    }
    // A signal interrupts poll (EINTR, the handlers do not restart calls); the timeout covers one
    // that arrives between the look at the flag and the call.
    pollfd entry{fd_, POLLIN, 0};
    const int ready = ::poll(&entry, 1, wake_up_ms_);
    if (ready == 0 || (ready < 0 && errno == EINTR)) continue;
    if (ready < 0) {
      error_number_ = errno;
      return false;
    }
    const ssize_t got = ::read(fd_, chunk, sizeof(chunk));
    if (got < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (got < 0) {
      error_number_ = errno;
      return false;
    }
    if (got == 0) return false;
    pending_.append(chunk, static_cast<std::size_t>(got));
    return true;
  }
}

StoppableLineBuf::int_type StoppableLineBuf::underflow() {
  if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
  while (true) {
    const std::size_t newline = pending_.rfind('\n');
    if (newline != std::string::npos || pending_.size() >= kMaxHeldBytes) {
      const std::size_t whole = newline != std::string::npos ? newline + 1 : pending_.size();
      lines_.assign(pending_, 0, whole);
      pending_.erase(0, whole);
      break;
    }
    if (!ReadMore()) {
      // A stop or a failed read drops the unfinished line; the end of the input hands it out.
      if (stopped_ || error_number_ != 0 || pending_.empty()) return traits_type::eof();
      lines_.swap(pending_);
      pending_.clear();
      break;
    }
  }
  setg(lines_.data(), lines_.data(), lines_.data() + lines_.size());
  return traits_type::to_int_type(*gptr());
}

}  // namespace hilrig::rig
