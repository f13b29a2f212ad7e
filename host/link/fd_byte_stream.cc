#include "host/link/fd_byte_stream.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "host/link/poll_wait.h"

namespace hilrig::host {
namespace {

// A hung-up terminal (a pseudo-terminal whose other side closed, an unplugged USB adapter) reads
// EIO; a socket reads ECONNRESET.
bool HungUp(int error) { return error == EIO || error == ECONNRESET || error == EPIPE; }

}  // namespace

FdByteStream::FdByteStream(int fd, bool socket, std::string name, std::shared_ptr<void> owner)
    : fd_(fd), socket_(socket), name_(std::move(name)), owner_(std::move(owner)) {}

rig::Result<void> FdByteStream::WriteAll(std::span<const std::uint8_t> bytes, int timeout_ms) {
  if (closed_) return rig::MakeError(rig::ErrorCode::kLinkClosed, name_ + ": closed by the peer");
  const Deadline deadline = DeadlineIn(timeout_ms);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t wrote =
        socket_ ? ::send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL | MSG_DONTWAIT)
                : ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (wrote > 0) {
      done += static_cast<std::size_t>(wrote);
      continue;
    }
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (WaitFor(fd_, POLLOUT, deadline) <= 0) {
        return rig::MakeError(rig::ErrorCode::kTimeout, name_ + ": write timed out after " +
                                                            std::to_string(timeout_ms) +
                                                            " ms (the peer does not read)");
      }
      continue;
    }
    const int error = wrote < 0 ? errno : EIO;
    if (HungUp(error)) closed_ = true;
    return rig::MakeError(closed_ ? rig::ErrorCode::kLinkClosed : rig::ErrorCode::kIo,
                          name_ + ": write: " + std::strerror(error));
  }
  return {};
}

StreamRead FdByteStream::ReadSome(std::span<std::uint8_t> out, int timeout_ms) {
  const Deadline deadline = DeadlineIn(timeout_ms);
  while (!closed_) {
    const ssize_t got = ::read(fd_, out.data(), out.size());
    if (got > 0) return {StreamStatus::kData, static_cast<std::size_t>(got), {}};
    if (got == 0 || HungUp(errno)) {
      closed_ = true;
      break;
    }
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      return {StreamStatus::kError, 0, name_ + ": read: " + std::strerror(errno)};
    }
    const int ready = WaitFor(fd_, POLLIN, deadline);
    if (ready == 0) return {};
    if (ready < 0) return {StreamStatus::kError, 0, name_ + ": poll: " + std::strerror(errno)};
  }
  return {StreamStatus::kClosed, 0, name_ + ": closed by the peer"};
}

}  // namespace hilrig::host
