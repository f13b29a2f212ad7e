// Argument parsing shared by the hilrig subcommands: positional arguments and "--flag value"
// options from a fixed list, with an error that names the offending argument.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "rig/result.h"

namespace hilrig::host {

struct CliStreams {
  std::ostream& out;
  std::ostream& err;
  const std::atomic<bool>* stop_requested;
};

struct CliArgs {
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;  // "--out" -> "DIR"

  const std::string* Option(const std::string& name) const;
};

// Parses args[1..] (args[0] is the subcommand); every option takes one value.
rig::Result<CliArgs> ParseCliArgs(const std::vector<std::string>& args,
                                  const std::set<std::string>& allowed_options);

rig::Result<std::uint64_t> ParseSeed(const std::string& text);

// The value of `option`: a whole number from `min` to `max`, the whole text and nothing else.
rig::Result<int> ParseWholeNumberOption(const std::string& option, const std::string& text, int min,
                                        int max);

}  // namespace hilrig::host
