#include "host/link/pseudo_terminal.h"

#include <fcntl.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "host/link/fd_byte_stream.h"

namespace hilrig::host {
namespace {

struct OwnedFd {
  explicit OwnedFd(int fd) : fd(fd) {}
  ~OwnedFd() {
    if (fd >= 0) ::close(fd);
  }
  OwnedFd(const OwnedFd&) = delete;
  OwnedFd& operator=(const OwnedFd&) = delete;
  int fd;
};

rig::Error Failed(const char* call) {
  return rig::MakeError(rig::ErrorCode::kIo,
                        std::string("pseudo-terminal: ") + call + ": " + std::strerror(errno));
}

}  // namespace

rig::Result<PseudoTerminal> OpenPseudoTerminal() {
  auto master = std::make_shared<OwnedFd>(::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC));
  if (master->fd < 0) return Failed("posix_openpt");
  if (::grantpt(master->fd) != 0) return Failed("grantpt");
  if (::unlockpt(master->fd) != 0) return Failed("unlockpt");
  const char* name = ::ptsname(master->fd);
  if (name == nullptr) return Failed("ptsname");
  PseudoTerminal pair;
  pair.slave_path = name;
  auto slave = std::make_shared<OwnedFd>(::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC));
  if (slave->fd < 0) return Failed("open the slave");
  termios mode{};
  if (::tcgetattr(slave->fd, &mode) != 0) return Failed("tcgetattr");
  ::cfmakeraw(&mode);
  if (::tcsetattr(slave->fd, TCSANOW, &mode) != 0) return Failed("tcsetattr");
  const int flags = ::fcntl(master->fd, F_GETFL);
  if (flags < 0 || ::fcntl(master->fd, F_SETFL, flags | O_NONBLOCK) != 0) {
    return Failed("non-blocking mode");
  }
  const int fd = master->fd;
  pair.master =
      std::make_unique<FdByteStream>(fd, /*socket=*/false, "pseudo-terminal " + pair.slave_path,
                                     std::shared_ptr<void>(master, master.get()));
  pair.slave_hold = std::shared_ptr<void>(slave, slave.get());
  return pair;
}

}  // namespace hilrig::host
