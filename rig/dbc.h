// A reader for the subset of Vector's DBC format that describes classic CAN message layouts: the
// node list (BU_), messages (BO_) and their signals (SG_) with start bit, length, byte order,
// sign, factor, offset, range, unit, receivers and simple multiplexing (M / mN). Everything else
// in a DBC file (comments, attributes, value tables) is skipped, so files written by CANdb++ or
// cantools load too. It exists so that proto/tactile.dbc, the layout other tools read, can be
// checked against the rig's own codec instead of trusted to agree with it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rig/result.h"

namespace hilrig::rig {

struct DbcSignal {
  std::string name;
  std::uint32_t start_bit = 0;  // DBC numbering: LSB for Intel, MSB (sawtooth) for Motorola
  std::uint32_t length_bits = 0;
  bool little_endian = true;  // @1 Intel; @0 Motorola
  bool is_signed = false;     // '-' two's complement; '+' unsigned
  double factor = 1;
  double offset = 0;
  double minimum = 0;
  double maximum = 0;
  std::string unit;
  std::vector<std::string> receivers;
  bool is_multiplexor = false;                   // "M"
  std::optional<std::uint32_t> multiplex_value;  // "mN": present only when the multiplexor is N

  double ToPhysical(std::int64_t raw) const { return double(raw) * factor + offset; }
};

struct DbcMessage {
  std::uint32_t id = 0;  // without the extended flag
  bool extended = false;
  std::string name;
  std::uint32_t length_bytes = 0;
  std::string transmitter;
  std::vector<DbcSignal> signals;

  const DbcSignal* FindSignal(std::string_view signal_name) const;
};

struct DbcDatabase {
  std::vector<std::string> nodes;
  std::vector<DbcMessage> messages;

  const DbcMessage* FindMessage(std::uint32_t id, bool extended = false) const;
};

// The largest DBC file read: a whole vehicle's database is a few MB.
inline constexpr std::size_t kMaxDbcFileBytes = std::size_t{16} << 20;

// Errors name the line number and what could not be read.
Result<DbcDatabase> ParseDbc(std::string_view text);
// A regular file of at most kMaxDbcFileBytes (rig::ReadRegularFile), parsed.
Result<DbcDatabase> LoadDbcFile(const std::string& path);

// The raw value of `signal` in `payload` (sign-extended when the signal is signed). Errors when the
// signal reaches past the payload or is longer than 64 bits.
Result<std::int64_t> ExtractRawSignal(const DbcSignal& signal,
                                      std::span<const std::uint8_t> payload);

}  // namespace hilrig::rig
