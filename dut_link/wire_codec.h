// The protobuf wire format, as much of it as the DUT's side of the HIL link needs: read the
// fields of a message one by one (varint, zigzag, fixed32 float, fixed64 double, length-delimited
// bytes and nested messages, packed repeated floats and doubles, unknown fields skipped) and write
// them into a buffer the caller owns. Written for the firmware rather than taken from nanopb:
// Debian ships nanopb's generator and an x86-64 library but not the runtime's sources the MCU
// would compile, and the messages are few enough to map by hand (dut_link/serial_session.h).
//
// Both sides keep a sticky error: after the first problem every read returns a zero value and
// Next() ends the message, every write is dropped, so a caller checks error() once at the end
// instead of after each call. Portable like the rest of dut_link: header-only, no allocation, no
// exceptions. Every function runs in time linear in the bytes it reads or writes (O(1) unless
// stated) and allocates nothing; whether a function can fail is stated with it.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace hilrig::dut_link::wire {

enum class WireType : std::uint8_t {
  kVarint = 0,
  kFixed64 = 1,
  kLengthDelimited = 2,
  kFixed32 = 5,
};

enum class WireError : std::uint8_t {
  kNone,
  kTruncated,       // a value or a length runs past the end of its message
  kBadWireType,     // a wire type the format does not have (or groups), or not the field's type
  kOverlongVarint,  // more than 10 bytes, or bits beyond 64
  kBadFieldNumber,  // field number 0
  kTooManyValues,   // a repeated field with more values than the caller's array holds
  kOverflow,        // the writer's buffer is full
};

struct Tag {
  std::uint32_t field = 0;
  WireType type = WireType::kVarint;
};

inline constexpr std::size_t kMaxVarintBytes = 10;

// sint32/sint64 on the wire. Cannot fail; O(1).
constexpr std::uint64_t ZigZagEncode(std::int64_t value) {
  return (std::uint64_t(value) << 1) ^ std::uint64_t(value >> 63);
}
constexpr std::int64_t ZigZagDecode(std::uint64_t value) {
  return std::int64_t(value >> 1) ^ -std::int64_t(value & 1);
}

// Reads one message (or a nested message's bytes). Usage:
//   while (auto tag = reader.Next()) switch (tag->field) { case proto_tags::M::kX: ...; }
//   if (reader.error() != WireError::kNone) ...
class Reader {
 public:
  // Reads `bytes`, which must outlive the reader and every view it hands out. Cannot fail.
  constexpr explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  // The next field's tag; nullopt at the end of the message or once an error is set. The caller
  // reads the field's value or Skip()s it before calling Next again (Next skips a value left
  // unread). Can fail: kTruncated, kOverlongVarint, kBadWireType, kBadFieldNumber.
  constexpr std::optional<Tag> Next() {
    if (pending_) Skip();
    if (error_ != WireError::kNone || at_ == bytes_.size()) return std::nullopt;
    const std::uint64_t key = ReadRawVarint();
    const auto type = std::uint8_t(key & 7);
    if (error_ != WireError::kNone) return std::nullopt;
    if (type != 0 && type != 1 && type != 2 && type != 5) return Fail(WireError::kBadWireType);
    if ((key >> 3) == 0 || (key >> 3) > 0x1FFFFFFF) return Fail(WireError::kBadFieldNumber);
    tag_ = {std::uint32_t(key >> 3), WireType(type)};
    pending_ = true;
    return tag_;
  }

  // The current field's value. Each can fail with kBadWireType (the field has another wire type)
  // or kTruncated; Varint also with kOverlongVarint. On failure they return 0 / false / empty.
  constexpr std::uint64_t Varint() {
    if (!Take(WireType::kVarint)) return 0;
    return ReadRawVarint();
  }
  constexpr std::uint32_t Uint32() { return std::uint32_t(Varint()); }  // truncates, as protobuf
  constexpr std::int64_t Int64() { return std::int64_t(Varint()); }
  constexpr std::int64_t SInt64() { return ZigZagDecode(Varint()); }
  constexpr std::int32_t SInt32() { return std::int32_t(ZigZagDecode(Varint())); }
  constexpr bool Bool() { return Varint() != 0; }
  constexpr float Float() {
    if (!Take(WireType::kFixed32)) return 0.f;
    return std::bit_cast<float>(std::uint32_t(ReadFixed(4)));
  }
  constexpr double Double() {
    if (!Take(WireType::kFixed64)) return 0.0;
    return std::bit_cast<double>(ReadFixed(8));
  }
  // A bytes or string field, as a view into the message.
  constexpr std::span<const std::uint8_t> Bytes() {
    if (!Take(WireType::kLengthDelimited)) return {};
    return ReadLengthDelimited();
  }
  // A nested message: a reader over its bytes (an empty one on failure).
  constexpr Reader Message() { return Reader(Bytes()); }

  // A repeated float (or double) field: appends its values to out[count..] and advances count.
  // Takes the packed form (proto3's default) and the unpacked one, one value per tag, so a field
  // may arrive in several pieces. Can fail: kTooManyValues, kTruncated (a packed length that is
  // not a multiple of the value size), kBadWireType. O(values).
  constexpr void AppendFloats(std::span<float> out, std::size_t& count) {
    AppendFixed<float, std::uint32_t, WireType::kFixed32>(out, count);
  }
  constexpr void AppendDoubles(std::span<double> out, std::size_t& count) {
    AppendFixed<double, std::uint64_t, WireType::kFixed64>(out, count);
  }

  // Skips the current field's value (an unknown field). Can fail: kTruncated, kOverlongVarint.
  constexpr void Skip() {
    if (!pending_) return;
    pending_ = false;
    switch (tag_.type) {
      case WireType::kVarint:
        ReadRawVarint();
        break;
      case WireType::kFixed64:
        ReadFixed(8);
        break;
      case WireType::kLengthDelimited:
        ReadLengthDelimited();
        break;
      case WireType::kFixed32:
        ReadFixed(4);
        break;
    }
  }

  constexpr WireError error() const { return error_; }
  constexpr bool ok() const { return error_ == WireError::kNone; }
  // Marks the message bad for a reason of the caller's (e.g. kTooManyValues for a repeated
  // message field it keeps in an array); the first error stays.
  constexpr void SetError(WireError error) {
    if (error_ == WireError::kNone) error_ = error;
  }

 private:
  constexpr std::nullopt_t Fail(WireError error) {
    SetError(error);
    pending_ = false;
    return std::nullopt;
  }

  // Consumes the pending tag if its wire type is `type`.
  constexpr bool Take(WireType type) {
    if (!pending_ || error_ != WireError::kNone) return false;
    pending_ = false;
    if (tag_.type != type) {
      SetError(WireError::kBadWireType);
      return false;
    }
    return true;
  }

  constexpr std::uint64_t ReadRawVarint() {
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < kMaxVarintBytes; ++i) {
      if (at_ == bytes_.size()) {
        SetError(WireError::kTruncated);
        return 0;
      }
      const std::uint8_t byte = bytes_[at_++];
      if (i == kMaxVarintBytes - 1 && byte > 1) break;  // bits beyond 64
      value |= std::uint64_t(byte & 0x7F) << (7 * i);
      if ((byte & 0x80) == 0) return value;
    }
    SetError(WireError::kOverlongVarint);
    return 0;
  }

  constexpr std::uint64_t ReadFixed(std::size_t size) {
    if (bytes_.size() - at_ < size) {
      SetError(WireError::kTruncated);
      at_ = bytes_.size();
      return 0;
    }
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < size; ++i) value |= std::uint64_t(bytes_[at_ + i]) << (8 * i);
    at_ += size;
    return value;
  }

  constexpr std::span<const std::uint8_t> ReadLengthDelimited() {
    const std::uint64_t length = ReadRawVarint();
    if (error_ != WireError::kNone) return {};
    if (length > bytes_.size() - at_) {
      SetError(WireError::kTruncated);
      at_ = bytes_.size();
      return {};
    }
    const std::span<const std::uint8_t> view = bytes_.subspan(at_, std::size_t(length));
    at_ += std::size_t(length);
    return view;
  }

  template <typename T, typename Bits, WireType kType>
  constexpr void AppendFixed(std::span<T> out, std::size_t& count) {
    if (!pending_ || error_ != WireError::kNone) return;
    if (tag_.type == kType) {
      const T value = std::bit_cast<T>(Bits(ReadFixed(sizeof(T))));
      pending_ = false;
      if (error_ != WireError::kNone) return;
      if (count == out.size()) return SetError(WireError::kTooManyValues);
      out[count++] = value;
      return;
    }
    const std::span<const std::uint8_t> packed = Bytes();
    if (error_ != WireError::kNone) return;
    if (packed.size() % sizeof(T) != 0) return SetError(WireError::kTruncated);
    if (packed.size() / sizeof(T) > out.size() - count) return SetError(WireError::kTooManyValues);
    for (std::size_t i = 0; i < packed.size(); i += sizeof(T)) {
      Bits bits = 0;
      for (std::size_t b = 0; b < sizeof(T); ++b) bits |= Bits(Bits(packed[i + b]) << (8 * b));
      out[count++] = std::bit_cast<T>(bits);
    }
  }

  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 0;
  Tag tag_;
  bool pending_ = false;  // a tag was read and its value not yet
  WireError error_ = WireError::kNone;
};

// Writes fields into the caller's buffer, in the order called. Like protobuf's own serializer the
// caller leaves out proto3 fields that hold their default, so the bytes match libprotobuf's. Every
// write can fail with kOverflow (the buffer is full): nothing of that field is written, the error
// sticks and every later write is dropped.
class Writer {
 public:
  // Writes into `out` from its start. Cannot fail.
  constexpr explicit Writer(std::span<std::uint8_t> out) : out_(out) {}

  constexpr void Varint(std::uint32_t field, std::uint64_t value) {
    if (!Room(KeyBytes(field) + VarintBytes(value))) return;
    PutKey(field, WireType::kVarint);
    PutVarint(value);
  }
  constexpr void SInt64(std::uint32_t field, std::int64_t value) {
    Varint(field, ZigZagEncode(value));
  }
  constexpr void Bool(std::uint32_t field, bool value) { Varint(field, value ? 1 : 0); }
  constexpr void Float(std::uint32_t field, float value) {
    if (!Room(KeyBytes(field) + 4)) return;
    PutKey(field, WireType::kFixed32);
    PutFixed(std::bit_cast<std::uint32_t>(value), 4);
  }
  constexpr void Double(std::uint32_t field, double value) {
    if (!Room(KeyBytes(field) + 8)) return;
    PutKey(field, WireType::kFixed64);
    PutFixed(std::bit_cast<std::uint64_t>(value), 8);
  }
  // proto3 leaves a field that holds its default off the wire, as libprotobuf does: these write
  // nothing for 0 (a bool's false), or for a double whose bits are all zero (-0.0 is written).
  constexpr void NonZeroVarint(std::uint32_t field, std::uint64_t value) {
    if (value != 0) Varint(field, value);
  }
  constexpr void NonZeroDouble(std::uint32_t field, double value) {
    if (std::bit_cast<std::uint64_t>(value) != 0) Double(field, value);
  }
  constexpr void Bytes(std::uint32_t field, std::span<const std::uint8_t> bytes) {
    if (!Room(KeyBytes(field) + VarintBytes(bytes.size()) + bytes.size())) return;
    PutKey(field, WireType::kLengthDelimited);
    PutVarint(bytes.size());
    for (const std::uint8_t byte : bytes) out_[size_++] = byte;
  }
  // A packed repeated float or double field; nothing for no values. O(values).
  constexpr void PackedFloats(std::uint32_t field, std::span<const float> values) {
    PackedFixed<std::uint32_t>(field, values);
  }
  constexpr void PackedDoubles(std::uint32_t field, std::span<const double> values) {
    PackedFixed<std::uint64_t>(field, values);
  }
  // A packed repeated varint field (uint32, uint64, enum); nothing for no values. O(values).
  template <typename Unsigned>
  constexpr void PackedVarints(std::uint32_t field, std::span<const Unsigned> values) {
    if (values.empty()) return;
    std::size_t length = 0;
    for (const Unsigned value : values) length += VarintBytes(value);
    if (!Room(KeyBytes(field) + VarintBytes(length) + length)) return;
    PutKey(field, WireType::kLengthDelimited);
    PutVarint(length);
    for (const Unsigned value : values) PutVarint(value);
  }

  // A nested message: BeginMessage writes the key and holds one byte for the length, the caller
  // writes the fields, EndMessage fills the length in (moving the fields up when it needs more
  // than one byte: O(message bytes) then).
  struct Nested {
    std::size_t length_at = 0;
  };
  constexpr Nested BeginMessage(std::uint32_t field) {
    if (!Room(KeyBytes(field) + 1)) return {};
    PutKey(field, WireType::kLengthDelimited);
    return {size_++};
  }
  constexpr void EndMessage(Nested nested) {
    if (error_ != WireError::kNone) return;
    const std::size_t body_at = nested.length_at + 1;
    const std::size_t length = size_ - body_at;
    const std::size_t extra = VarintBytes(length) - 1;
    if (!Room(extra)) return;
    for (std::size_t i = size_; i-- > body_at;) out_[i + extra] = out_[i];
    size_ = nested.length_at;
    PutVarint(length);
    size_ = body_at + extra + length;
  }

  // What was written; a message only when ok() (after an overflow a nested length may be left
  // unfilled). Cannot fail; O(1).
  constexpr std::span<const std::uint8_t> written() const { return out_.first(size_); }
  constexpr std::size_t size() const { return size_; }
  constexpr WireError error() const { return error_; }
  constexpr bool ok() const { return error_ == WireError::kNone; }

  // The bytes `value` takes as a varint. Cannot fail; O(1).
  static constexpr std::size_t VarintBytes(std::uint64_t value) {
    std::size_t bytes = 1;
    while (value >= 0x80) {
      value >>= 7;
      ++bytes;
    }
    return bytes;
  }

 private:
  static constexpr std::size_t KeyBytes(std::uint32_t field) {
    return VarintBytes(std::uint64_t(field) << 3);
  }
  template <typename Bits, typename Value>
  constexpr void PackedFixed(std::uint32_t field, std::span<const Value> values) {
    if (values.empty()) return;
    const std::size_t length = sizeof(Bits) * values.size();
    if (!Room(KeyBytes(field) + VarintBytes(length) + length)) return;
    PutKey(field, WireType::kLengthDelimited);
    PutVarint(length);
    for (const Value value : values) PutFixed(std::bit_cast<Bits>(value), sizeof(Bits));
  }
  constexpr bool Room(std::size_t bytes) {
    if (error_ != WireError::kNone) return false;
    if (out_.size() - size_ >= bytes) return true;
    error_ = WireError::kOverflow;
    return false;
  }
  constexpr void PutKey(std::uint32_t field, WireType type) {
    PutVarint((std::uint64_t(field) << 3) | std::uint64_t(type));
  }
  constexpr void PutVarint(std::uint64_t value) {
    while (value >= 0x80) {
      out_[size_++] = std::uint8_t(value | 0x80);
      value >>= 7;
    }
    out_[size_++] = std::uint8_t(value);
  }
  constexpr void PutFixed(std::uint64_t bits, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) out_[size_++] = std::uint8_t(bits >> (8 * i));
  }

  std::span<std::uint8_t> out_;
  std::size_t size_ = 0;
  WireError error_ = WireError::kNone;
};

}  // namespace hilrig::dut_link::wire
