#include "host/cli/cli_args.h"

#include <charconv>

namespace hilrig::host {

const std::string* CliArgs::Option(const std::string& name) const {
  const auto found = options.find(name);
  return found == options.end() ? nullptr : &found->second;
}

rig::Result<CliArgs> ParseCliArgs(const std::vector<std::string>& args,
                                  const std::set<std::string>& allowed_options) {
  CliArgs parsed;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (!arg.starts_with("--")) {
      parsed.positional.push_back(arg);
      continue;
    }
    if (!allowed_options.contains(arg)) return rig::MakeError("unknown option " + arg);
    if (i + 1 >= args.size()) return rig::MakeError(arg + " needs a value");
    parsed.options[arg] = args[++i];
  }
  return parsed;
}

rig::Result<std::uint64_t> ParseSeed(const std::string& text) {
  std::uint64_t seed = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), seed);
  if (error != std::errc() || end != text.data() + text.size()) {
    return rig::MakeError("--seed must be a non-negative integer, got \"" + text + "\"");
  }
  return seed;
}

rig::Result<int> ParseWholeNumberOption(const std::string& option, const std::string& text, int min,
                                        int max) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < min || value > max) {
    return rig::MakeError(option + " must be a whole number from " + std::to_string(min) + " to " +
                          std::to_string(max) + ", got \"" + text + "\"");
  }
  return value;
}

}  // namespace hilrig::host
