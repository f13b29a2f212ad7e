#include "host/cli/cli_args.h"

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

}  // namespace hilrig::host
