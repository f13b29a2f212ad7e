#include "rig/dbc.h"

#include <charconv>
#include <sstream>

#include "rig/can_bus.h"
#include "rig/file_io.h"

namespace hilrig::rig {
namespace {

// A cursor over one line; every Read* skips leading blanks first.
class LineReader {
 public:
  explicit LineReader(std::string_view line) : rest_(line) {}

  void SkipBlanks() {
    while (!rest_.empty() && (rest_.front() == ' ' || rest_.front() == '\t'))
      rest_.remove_prefix(1);
  }
  bool Consume(char c) {
    SkipBlanks();
    if (rest_.empty() || rest_.front() != c) return false;
    rest_.remove_prefix(1);
    return true;
  }
  // A run of characters up to a blank or one of `stops`.
  std::string_view Token(std::string_view stops = "") {
    SkipBlanks();
    std::size_t n = 0;
    while (n < rest_.size() && rest_[n] != ' ' && rest_[n] != '\t' &&
           stops.find(rest_[n]) == std::string_view::npos) {
      ++n;
    }
    const std::string_view token = rest_.substr(0, n);
    rest_.remove_prefix(n);
    return token;
  }
  std::optional<std::uint64_t> Unsigned(std::string_view stops = "") {
    const std::string_view token = Token(stops);
    std::uint64_t value = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (token.empty() || ec != std::errc() || end != token.data() + token.size()) {
      return std::nullopt;
    }
    return value;
  }
  std::optional<double> Number(std::string_view stops) {
    const std::string token(Token(stops));
    if (token.empty()) return std::nullopt;
    std::istringstream in(token);
    in.imbue(std::locale::classic());
    double value = 0;
    if (!(in >> value) || in.peek() != std::char_traits<char>::eof()) return std::nullopt;
    return value;
  }
  std::optional<std::string> Quoted() {
    if (!Consume('"')) return std::nullopt;
    const std::size_t end = rest_.find('"');
    if (end == std::string_view::npos) return std::nullopt;
    std::string text(rest_.substr(0, end));
    rest_.remove_prefix(end + 1);
    return text;
  }
  std::string_view rest() const { return rest_; }

 private:
  std::string_view rest_;
};

Error LineError(std::size_t line_number, const std::string& problem) {
  return MakeError("dbc line " + std::to_string(line_number) + ": " + problem);
}

// BO_ <id> <name>: <dlc> <transmitter>
Result<DbcMessage> ParseMessage(LineReader& line, std::size_t line_number) {
  DbcMessage message;
  const std::optional<std::uint64_t> id = line.Unsigned();
  if (!id || *id > 0xFFFFFFFFu) return LineError(line_number, "BO_ needs a numeric id");
  message.extended = (*id & kCanEffFlag) != 0;
  message.id = static_cast<std::uint32_t>(*id & ~kCanEffFlag);
  message.name = std::string(line.Token(":"));
  if (message.name.empty() || !line.Consume(':')) {
    return LineError(line_number, "BO_ needs '<name>:'");
  }
  const std::optional<std::uint64_t> dlc = line.Unsigned();
  if (!dlc || *dlc > 64) return LineError(line_number, "BO_ needs a length of 0..64 bytes");
  message.length_bytes = static_cast<std::uint32_t>(*dlc);
  message.transmitter = std::string(line.Token());
  return message;
}

Result<void> ParseMultiplexIndicator(std::string_view indicator, DbcSignal& signal,
                                     std::size_t line_number) {
  if (indicator == "M") {
    signal.is_multiplexor = true;
    return {};
  }
  std::uint32_t value = 0;
  const auto [end, ec] =
      std::from_chars(indicator.data() + 1, indicator.data() + indicator.size(), value);
  if (indicator.size() < 2 || indicator[0] != 'm' || ec != std::errc() ||
      end != indicator.data() + indicator.size()) {
    return LineError(line_number,
                     "unsupported multiplex indicator '" + std::string(indicator) + "'");
  }
  signal.multiplex_value = value;
  return {};
}

// SG_ <name> [M|mN] : <start>|<length>@<order><sign> (<factor>,<offset>) [<min>|<max>] "<unit>"
// <receivers>
Result<DbcSignal> ParseSignal(LineReader& line, std::size_t line_number) {
  DbcSignal signal;
  signal.name = std::string(line.Token(":"));
  if (signal.name.empty()) return LineError(line_number, "SG_ needs a name");
  if (!line.Consume(':')) {
    const std::string_view indicator = line.Token(":");
    if (Result<void> mux = ParseMultiplexIndicator(indicator, signal, line_number); !mux) {
      return mux.error();
    }
    if (!line.Consume(':')) return LineError(line_number, "SG_ needs ':' after the name");
  }
  const std::optional<std::uint64_t> start = line.Unsigned("|");
  const bool bar = line.Consume('|');
  const std::optional<std::uint64_t> length = line.Unsigned("@");
  if (!start || !bar || !length || !line.Consume('@') || *start > 511 || *length == 0 ||
      *length > 64) {
    return LineError(line_number, "SG_ needs '<start>|<length>@' with a length of 1..64");
  }
  signal.start_bit = static_cast<std::uint32_t>(*start);
  signal.length_bits = static_cast<std::uint32_t>(*length);
  const std::string_view order_sign = line.Token("(");
  if (order_sign.size() != 2 || (order_sign[0] != '0' && order_sign[0] != '1') ||
      (order_sign[1] != '+' && order_sign[1] != '-')) {
    return LineError(line_number, "SG_ byte order and sign must be one of 0+ 0- 1+ 1-");
  }
  signal.little_endian = order_sign[0] == '1';
  signal.is_signed = order_sign[1] == '-';
  const bool open_paren = line.Consume('(');
  const std::optional<double> factor = line.Number(",");
  const bool comma = line.Consume(',');
  const std::optional<double> offset = line.Number(")");
  if (!open_paren || !factor || !comma || !offset || !line.Consume(')')) {
    return LineError(line_number, "SG_ needs '(<factor>,<offset>)'");
  }
  const bool open_bracket = line.Consume('[');
  const std::optional<double> minimum = line.Number("|");
  const bool range_bar = line.Consume('|');
  const std::optional<double> maximum = line.Number("]");
  if (!open_bracket || !minimum || !range_bar || !maximum || !line.Consume(']')) {
    return LineError(line_number, "SG_ needs '[<min>|<max>]'");
  }
  const std::optional<std::string> unit = line.Quoted();
  if (!unit) return LineError(line_number, "SG_ needs a quoted unit");
  signal.factor = *factor;
  signal.offset = *offset;
  signal.minimum = *minimum;
  signal.maximum = *maximum;
  signal.unit = *unit;
  for (std::string_view receiver = line.Token(","); !receiver.empty(); receiver = line.Token(",")) {
    signal.receivers.emplace_back(receiver);
    line.Consume(',');
  }
  return signal;
}

bool PayloadBit(std::span<const std::uint8_t> payload, std::uint32_t bit) {
  return ((payload[bit / 8] >> (bit % 8)) & 1u) != 0;
}

}  // namespace

const DbcSignal* DbcMessage::FindSignal(std::string_view signal_name) const {
  for (const DbcSignal& signal : signals) {
    if (signal.name == signal_name) return &signal;
  }
  return nullptr;
}

const DbcMessage* DbcDatabase::FindMessage(std::uint32_t id, bool extended) const {
  for (const DbcMessage& message : messages) {
    if (message.id == id && message.extended == extended) return &message;
  }
  return nullptr;
}

Result<DbcDatabase> ParseDbc(std::string_view text) {
  DbcDatabase database;
  DbcMessage* current = nullptr;  // the BO_ that SG_ lines belong to
  std::size_t line_number = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    std::string_view raw = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++line_number;
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    LineReader line(raw);
    const std::string_view keyword = line.Token(":");
    if (keyword == "BU_") {
      if (!line.Consume(':')) return LineError(line_number, "BU_ needs ':'");
      for (std::string_view node = line.Token(); !node.empty(); node = line.Token()) {
        database.nodes.emplace_back(node);
      }
    } else if (keyword == "BO_") {
      Result<DbcMessage> message = ParseMessage(line, line_number);
      if (!message) return message.error();
      database.messages.push_back(std::move(message).value());
      current = &database.messages.back();
    } else if (keyword == "SG_") {
      if (current == nullptr) return LineError(line_number, "SG_ outside a BO_");
      Result<DbcSignal> signal = ParseSignal(line, line_number);
      if (!signal) return signal.error();
      current->signals.push_back(std::move(signal).value());
    } else if (!keyword.empty()) {
      current = nullptr;  // any other statement ends the message's signal list
    }
  }
  return database;
}

Result<DbcDatabase> LoadDbcFile(const std::string& path) {
  Result<std::string> text = ReadRegularFile(path, kMaxDbcFileBytes);
  if (!text) return text.error();
  Result<DbcDatabase> database = ParseDbc(text.value());
  if (!database) return MakeError(path + ": " + database.error().message);
  return database;
}

Result<std::int64_t> ExtractRawSignal(const DbcSignal& signal,
                                      std::span<const std::uint8_t> payload) {
  if (signal.length_bits == 0 || signal.length_bits > 64) {
    return MakeError("signal " + signal.name + ": length must be 1..64 bits");
  }
  const std::uint32_t payload_bits = static_cast<std::uint32_t>(payload.size() * 8);
  std::uint64_t raw = 0;
  std::uint32_t bit = signal.start_bit;
  for (std::uint32_t i = 0; i < signal.length_bits; ++i) {
    if (bit >= payload_bits) {
      return MakeError("signal " + signal.name + " reaches past the " +
                       std::to_string(payload.size()) + "-byte payload");
    }
    if (signal.little_endian) {
      raw |= std::uint64_t(PayloadBit(payload, bit)) << i;
      ++bit;
    } else {
      // Motorola: start at the MSB, walk down within a byte, then to bit 7 of the next byte.
      raw = (raw << 1) | std::uint64_t(PayloadBit(payload, bit));
      bit = (bit % 8 == 0) ? bit + 15 : bit - 1;
    }
  }
  if (signal.is_signed && signal.length_bits < 64 && (raw >> (signal.length_bits - 1)) & 1u) {
    raw |= ~std::uint64_t(0) << signal.length_bits;  // sign-extend
  }
  return static_cast<std::int64_t>(raw);
}

}  // namespace hilrig::rig
