#include "rig/folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>

#include "rig/file_io.h"

namespace hilrig::rig {
namespace {

constexpr std::size_t kCommandShownChars = 200;

// A process's command line from the kernel, arguments separated by blanks, anything unprintable
// as '?', cut at kCommandShownChars; "" when it cannot be read (the process has ended).
std::string CommandLineOf(const std::string& pid) {
  auto bytes = ReadRegularFile("/proc/" + pid + "/cmdline", 4096);
  if (!bytes) return "";
  std::string command;
  for (const char c : bytes.value()) {
    if (command.size() == kCommandShownChars) return command + "...";
    const auto byte = static_cast<unsigned char>(c);
    command += c == '\0' ? ' ' : (std::isprint(byte) != 0 ? c : '?');
  }
  while (!command.empty() && command.back() == ' ') command.pop_back();
  return command;
}

// "pid 1234 (hilrig run a.textproto)": the pid from the lock file's first line, read as a number
// and nothing else, and the command from the kernel, so a planted lock file cannot put text of
// its own into the message.
std::string HolderOf(int fd) {
  char head[32] = {};
  const ssize_t got = ::pread(fd, head, sizeof(head) - 1, 0);
  constexpr std::string_view kPrefix = "pid ";
  const std::string_view text(head, got > 0 ? static_cast<std::size_t>(got) : 0);
  long pid = 0;
  const char* digits = text.data() + kPrefix.size();
  const char* end = text.data() + text.size();
  if (!text.starts_with(kPrefix) || std::from_chars(digits, end, pid).ec != std::errc() ||
      pid <= 0) {
    return "a process whose pid the lock file does not give yet";
  }
  const std::string number = std::to_string(pid);
  const std::string command = CommandLineOf(number);
  return "pid " + number + (command.empty() ? "" : " (" + command + ")");
}

Error LockError(const std::string& folder, const std::string& cause) {
  return MakeError("cannot take " + folder + " for this run: " + cause);
}

}  // namespace

Result<FolderLock> FolderLock::Acquire(const std::string& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) return MakeError("cannot create " + folder + ": " + error.message());
  const std::string path = (std::filesystem::path(folder) / kFolderLockFileName).string();
  // Non-blocking and without a controlling terminal: a FIFO or device planted at the name is
  // opened without waiting, then refused below.
  const int fd =
      ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK | O_NOCTTY, 0644);
  if (fd < 0) {
    return LockError(folder, path + (errno == ELOOP ? " is a symbolic link, which is not followed"
                                                    : ": " + std::string(std::strerror(errno))));
  }
  FolderLock lock(fd);  // closes the file on every return below that is not a success
  struct stat status {};
  if (::fstat(fd, &status) != 0) return LockError(folder, path + ": " + std::strerror(errno));
  if (!S_ISREG(status.st_mode)) return LockError(folder, path + " is not a regular file");
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno == EWOULDBLOCK) {
      return MakeError(folder + " is in use by another hilrig process: " + HolderOf(fd));
    }
    return LockError(folder, path + ": " + std::strerror(errno));
  }
  const std::string pid = std::to_string(::getpid());
  const std::string holder = "pid " + pid + "\ncommand " + CommandLineOf(pid) + "\n";
  if (::ftruncate(fd, 0) != 0 ||
      ::pwrite(fd, holder.data(), holder.size(), 0) != static_cast<ssize_t>(holder.size())) {
    return LockError(folder, WriteError(path, errno).message);
  }
  return lock;
}

FolderLock::FolderLock(FolderLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

FolderLock& FolderLock::operator=(FolderLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace hilrig::rig
