#include "host/cli/cli_args.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <exception>

namespace hilrig::host {

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

bool TakeFlag(std::vector<std::string>& args, const std::string& flag) {
  if (args.empty()) return false;
  const auto removed = std::remove(args.begin() + 1, args.end(), flag);
  const bool present = removed != args.end();
  args.erase(removed, args.end());
  return present;
}

rig::Result<double> ParseDurationOption(const std::string& text) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(value) || !(value > 0)) {
    return rig::MakeError("--duration-s must be a positive number of seconds, got \"" + text +
                          "\"");
  }
  return value;
}

rig::Result<std::vector<std::pair<std::string, double>>> ParseSetOption(const std::string& text) {
  std::vector<std::pair<std::string, double>> sets;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string part = text.substr(start, comma - start);
    start = comma + 1;
    const std::size_t equals = part.find('=');
    if (equals == std::string::npos || equals == 0) {
      return rig::MakeError("--set \"" + text + "\": expected PATH=VALUE[,PATH=VALUE...], got \"" +
                            part + "\"");
    }
    auto value =
        rig::ParseNumber<double>(part.substr(equals + 1), "--set " + part.substr(0, equals));
    if (!value) return value.error();
    sets.emplace_back(part.substr(0, equals), value.value());
  }
  return sets;
}

}  // namespace hilrig::host
