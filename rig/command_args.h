// Command-line arguments shared by the rig's executables (hilrig's subcommands, dut_emu):
// positional arguments and "--flag value" options from a fixed list, with an error that names the
// offending argument, and whole numbers that must be the whole text.
#pragma once

#include <charconv>
#include <map>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "rig/result.h"

namespace hilrig::rig {

struct CliArgs {
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;  // "--out" -> "DIR"

  const std::string* Option(const std::string& name) const;
};

// " (did you mean X?)" when `word` is within two edits of one of `candidates` (the closest, the
// first of equals), else "". O(candidates x |word| x |candidate|); allocates.
std::string DidYouMean(const std::string& word, const std::set<std::string>& candidates);

// Parses args[1..] (args[0] is the command or subcommand); every option takes one value. An unknown
// option's error suggests the nearest allowed one, or the nearest of `flags`: the command's options
// without a value, which it took out of `args` before (DidYouMean).
Result<CliArgs> ParseCliArgs(const std::vector<std::string>& args,
                             const std::set<std::string>& allowed_options,
                             const std::set<std::string>& flags = {});

// `text` as a T, all of it; the error names `what` and quotes the text.
template <typename T>
Result<T> ParseNumber(const std::string& text, const std::string& what) {
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) {
    return MakeError(what + " \"" + text + "\" is not a valid number");
  }
  return value;
}

}  // namespace hilrig::rig
