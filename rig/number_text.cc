#include "rig/number_text.h"

#include <array>
#include <charconv>
#include <cmath>

namespace hilrig::rig {

std::string SecondsText(double seconds) { return NumberText(seconds) + " s"; }

std::string NumberText(double value) {
  // The sign of a NaN says nothing, and printf would show it ("-nan").
  if (!std::isfinite(value)) return std::isnan(value) ? "nan" : (value > 0 ? "inf" : "-inf");
  // printf's %.6g, without a locale: to_chars with six significant digits.
  std::array<char, 32> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value,
                                          std::chars_format::general, 6);
  if (error != std::errc()) return "0";  // unreachable: 32 characters hold any %.6g
  return std::string(buffer.data(), end);
}

std::string ExactNumber(double value) {
  std::array<char, 32> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  if (error != std::errc()) return "nan";  // unreachable: 32 characters hold any double
  return std::string(buffer.data(), end);
}

std::string FactorText(double factor) {
  if (!std::isfinite(factor)) return NumberText(factor) + "x";
  std::array<char, 32> buffer{};
  const bool whole = factor >= 10 && factor < 1e15;
  const auto [end, error] = whole ? std::to_chars(buffer.data(), buffer.data() + buffer.size(),
                                                  factor, std::chars_format::fixed, 0)
                                  : std::to_chars(buffer.data(), buffer.data() + buffer.size(),
                                                  factor, std::chars_format::general, 2);
  if (error != std::errc()) return "0x";  // unreachable: 32 characters hold either form
  return std::string(buffer.data(), end) + "x";
}

}  // namespace hilrig::rig
