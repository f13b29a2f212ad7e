#include "host/link/link_token.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "rig/os_random.h"

namespace hilrig::host {
namespace {

// Far more than a token and a newline; bounds what a wrong path (a log, /dev/zero) can cost.
constexpr std::size_t kMaxTokenFileBytes = 256;

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string ErrnoText() { return std::strerror(errno); }

// Closes the descriptor on every return path.
struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string LinkToken::Hex() const {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text;
  for (std::uint8_t byte : bytes) {
    text.push_back(kDigits[byte >> 4]);
    text.push_back(kDigits[byte & 0xF]);
  }
  return text;
}

rig::Result<LinkToken> NewLinkToken() {
  LinkToken token;
  if (auto filled = rig::FillWithOsRandomBytes(token.bytes); !filled) {
    return rig::MakeError("cannot make a link token: " + filled.error().message);
  }
  return token;
}

rig::Result<LinkToken> ParseLinkToken(std::string_view text) {
  while (!text.empty() && std::strchr(" \t\r\n", text.back()) != nullptr) text.remove_suffix(1);
  LinkToken token;
  if (text.size() != 2 * token.bytes.size()) {
    return rig::MakeError("a link token is " + std::to_string(2 * token.bytes.size()) +
                          " hex digits, not " + std::to_string(text.size()) + " characters");
  }
  for (std::size_t i = 0; i < token.bytes.size(); ++i) {
    const int high = HexDigit(text[2 * i]);
    const int low = HexDigit(text[2 * i + 1]);
    if (high < 0 || low < 0) return rig::MakeError("a link token is hex digits only");
    token.bytes[i] = static_cast<std::uint8_t>(high << 4 | low);
  }
  return token;
}

rig::Result<LinkToken> ReadLinkTokenFile(const std::string& path) {
  // O_NONBLOCK: a FIFO at the path must not block the open; it is refused below.
  FileDescriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (file.fd < 0) return rig::MakeError("link token file " + path + ": " + ErrnoText());
  struct stat status {};
  if (::fstat(file.fd, &status) != 0) {
    return rig::MakeError("link token file " + path + ": " + ErrnoText());
  }
  if (!S_ISREG(status.st_mode)) {
    return rig::MakeError("link token file " + path + ": not a regular file");
  }
  if (static_cast<std::size_t>(status.st_size) > kMaxTokenFileBytes) {
    return rig::MakeError("link token file " + path + ": larger than " +
                          std::to_string(kMaxTokenFileBytes) + " bytes");
  }
  std::string text(kMaxTokenFileBytes, '\0');
  std::size_t size = 0;
  while (size < text.size()) {
    const ssize_t got = ::read(file.fd, text.data() + size, text.size() - size);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) return rig::MakeError("link token file " + path + ": " + ErrnoText());
    if (got == 0) break;
    size += static_cast<std::size_t>(got);
  }
  auto token = ParseLinkToken(std::string_view(text.data(), size));
  if (!token) return rig::MakeError("link token file " + path + ": " + token.error().message);
  return token;
}

rig::Result<LinkToken> ReadOrCreateLinkTokenFile(const std::string& path, bool* created) {
  *created = false;
  auto token = NewLinkToken();
  if (!token) return token.error();
  // O_EXCL: a file that is there, or appears meanwhile, is read, never replaced.
  FileDescriptor file{::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600)};
  if (file.fd < 0) {
    if (errno == EEXIST) return ReadLinkTokenFile(path);
    return rig::MakeError("link token file " + path + ": " + ErrnoText());
  }
  const std::string text = token.value().Hex() + "\n";
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t put = ::write(file.fd, text.data() + written, text.size() - written);
    if (put < 0 && errno == EINTR) continue;
    if (put < 0) return rig::MakeError("link token file " + path + ": " + ErrnoText());
    written += static_cast<std::size_t>(put);
  }
  *created = true;
  return token;
}

bool ProvesLinkToken(const LinkToken& token, std::string_view proof) {
  if (proof.size() != token.bytes.size()) return false;
  std::uint8_t difference = 0;
  for (std::size_t i = 0; i < token.bytes.size(); ++i) {
    difference |= static_cast<std::uint8_t>(token.bytes[i] ^ static_cast<std::uint8_t>(proof[i]));
  }
  return difference == 0;
}

}  // namespace hilrig::host
