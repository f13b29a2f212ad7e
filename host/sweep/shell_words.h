// Words for the command lines and batch scripts a sweep writes (failing.txt, the Slurm jobs): a
// path or value with a space or a quote must reach the shell as one word, unchanged.
#pragma once

#include <string>

namespace hilrig::host {

// `text` single-quoted for bash unless it is made only of characters no shell treats specially.
// Cannot fail.
inline std::string ShellQuoted(const std::string& text) {
  if (!text.empty() &&
      text.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                             "_-./=,:+") == std::string::npos) {
    return text;
  }
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace hilrig::host
