// Test vectors for checking the MAVLink codec against an implementation written elsewhere
// (tests/host/mavlink/node_mavlink_test.sh). Two commands, each printing JSON on stdout:
//
//   mavlink_vectors tlog FILE   writes a telemetry log with one frame of every message the codec
//                               knows, each field set to a distinct value of its type, and prints
//                               those values by the definition's field names
//   mavlink_vectors read FILE   parses a raw byte stream of frames and prints each decoded frame's
//                               fields by the same names, then the parser's counters
//
// The values are written through the codec's field table and each frame is then decoded into its
// typed message and encoded again, which must give the same bytes: so the other implementation,
// reading by the message definitions, checks the typed layout too.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include "host/mavlink/mavlink_frame.h"
#include "host/mavlink/mavlink_messages.h"
#include "host/mavlink/tlog.h"

namespace {

using hilrig::mavlink::FieldInfo;
using hilrig::mavlink::Frame;
using hilrig::mavlink::MessageInfo;

template <typename T>
T Load(const std::uint8_t* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof value);  // the wire is little-endian, as this host
  return value;
}

template <typename T>
void Store(std::uint8_t* bytes, T value) {
  std::memcpy(bytes, &value, sizeof value);
}

// One element of `field` at `at` as JSON: 64-bit integers as strings (JSON numbers are doubles),
// floats with enough digits to read back the same float.
std::string ElementJson(const FieldInfo& field, const std::uint8_t* at) {
  const std::string_view type = field.type_name;
  char text[64];
  if (type == "float") {
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(Load<float>(at)));
  } else if (type == "double") {
    std::snprintf(text, sizeof text, "%.17g", Load<double>(at));
  } else if (type == "uint64_t") {
    std::snprintf(text, sizeof text, "\"%llu\"",
                  static_cast<unsigned long long>(Load<std::uint64_t>(at)));
  } else if (type == "int64_t") {
    std::snprintf(text, sizeof text, "\"%lld\"", static_cast<long long>(Load<std::int64_t>(at)));
  } else if (type == "uint32_t") {
    std::snprintf(text, sizeof text, "%u", Load<std::uint32_t>(at));
  } else if (type == "int32_t") {
    std::snprintf(text, sizeof text, "%d", Load<std::int32_t>(at));
  } else if (type == "uint16_t") {
    std::snprintf(text, sizeof text, "%u", unsigned{Load<std::uint16_t>(at)});
  } else if (type == "int16_t") {
    std::snprintf(text, sizeof text, "%d", int{Load<std::int16_t>(at)});
  } else if (type == "int8_t") {
    std::snprintf(text, sizeof text, "%d", int{Load<std::int8_t>(at)});
  } else {
    std::snprintf(text, sizeof text, "%u", unsigned{*at});  // uint8_t, char
  }
  return text;
}

// A distinct value for element `element` of field number `index`, in range for its type.
void StoreValue(const FieldInfo& field, int index, int element, std::uint8_t* at) {
  const std::string_view type = field.type_name;
  const int k = 7 * index + element + 1;
  if (type == "float") {
    Store(at, static_cast<float>(k) * 1.25f - 3.3f);
  } else if (type == "double") {
    Store(at, k * 0.1 - 1.0);
  } else if (type == "uint64_t") {
    Store(at, std::uint64_t{1'700'000'000'123'456} + std::uint64_t(k) * 1000);
  } else if (type == "int64_t") {
    Store(at, std::int64_t{-5'000'000'000} + k);
  } else if (type == "uint32_t") {
    Store(at, std::uint32_t(4'000'000'000u - k));
  } else if (type == "int32_t") {
    Store(at, std::int32_t(-1'000'000 * k));
  } else if (type == "uint16_t") {
    Store(at, std::uint16_t(60'000 - k));
  } else if (type == "int16_t") {
    Store(at, std::int16_t(-300 * k));
  } else if (type == "int8_t") {
    Store(at, std::int8_t(-k));
  } else if (type == "char") {
    *at = static_cast<std::uint8_t>('a' + k % 26);  // text, as a char array holds
  } else {
    *at = static_cast<std::uint8_t>(200 - k);
  }
}

std::string FieldsJson(const MessageInfo& info, const Frame& frame) {
  std::string json = "{";
  for (std::size_t i = 0; i < info.fields.size(); ++i) {
    const FieldInfo& field = info.fields[i];
    json += (i ? ", \"" : "\"") + std::string(field.name) + "\": ";
    const std::uint8_t* at = frame.payload.data() + field.offset;
    if (field.array_length == 0) {
      json += ElementJson(field, at);
      continue;
    }
    json += "[";
    for (int e = 0; e < field.array_length; ++e) {
      json += (e ? ", " : "") + ElementJson(field, at + e * field.element_bytes);
    }
    json += "]";
  }
  return json + "}";
}

std::string FrameJson(const MessageInfo& info, const Frame& frame, std::uint64_t time_us) {
  return "{\"id\": " + std::to_string(info.id) + ", \"name\": \"" + std::string(info.name) +
         "\", \"time_us\": \"" + std::to_string(time_us) +
         "\", \"payload_length\": " + std::to_string(frame.payload_length) +
         ", \"fields\": " + FieldsJson(info, frame) + "}";
}

int WriteTlog(const char* path) {
  std::ofstream out(path, std::ios::binary);
  hilrig::mavlink::TlogWriter tlog(out);
  std::cout << "[";
  std::uint8_t sequence = 0;
  std::uint64_t time_us = 1'000'000;
  for (const MessageInfo& info : hilrig::mavlink::AllMessages()) {
    Frame frame;
    frame.sequence = sequence++;
    frame.system_id = 1;
    frame.component_id = 51;
    frame.message_id = info.id;
    frame.payload_length = info.full_payload_bytes;
    for (std::size_t i = 0; i < info.fields.size(); ++i) {
      const FieldInfo& field = info.fields[i];
      for (int e = 0; e < std::max(1, int{field.array_length}); ++e) {
        StoreValue(field, int(i), e, frame.payload.data() + field.offset + e * field.element_bytes);
      }
    }
    std::array<std::uint8_t, hilrig::mavlink::kMaxFrameBytes> bytes;
    const std::size_t size = hilrig::mavlink::EncodeFrame(frame, info.crc_extra, bytes);
    // The typed path must give the same frame: decode into the struct, encode from it.
    const auto typed = hilrig::mavlink::DecodeMessage(frame);
    std::array<std::uint8_t, hilrig::mavlink::kMaxFrameBytes> again;
    const std::size_t again_size =
        typed ? hilrig::mavlink::EncodeMessage(*typed, frame.sequence, 1, 51, again) : 0;
    if (size == 0 || again_size != size ||
        !std::equal(bytes.begin(), bytes.begin() + size, again.begin())) {
      std::cerr << "mavlink_vectors: " << info.name << " does not round-trip its typed struct\n";
      return 1;
    }
    if (!tlog.Write(time_us, std::span(bytes.data(), size))) {
      std::cerr << "mavlink_vectors: cannot write " << path << "\n";
      return 1;
    }
    std::cout << (info.id == hilrig::mavlink::AllMessages().front().id ? "\n" : ",\n")
              << FrameJson(info, frame, time_us);
    time_us += 4000;
  }
  std::cout << "\n]\n";
  return out.good() ? 0 : 1;
}

int ReadStream(const char* path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
  hilrig::mavlink::FrameParser parser(&hilrig::mavlink::FindWireInfo);
  std::cout << "{\"frames\": [";
  bool first = true;
  parser.Feed(bytes, [&](const Frame& frame) {
    const MessageInfo* info = hilrig::mavlink::FindMessage(frame.message_id);
    if (!info) return;
    std::cout << (first ? "\n" : ",\n") << FrameJson(*info, frame, 0);
    first = false;
  });
  parser.Finish();
  while (auto frame = parser.Next()) {
    if (const MessageInfo* info = hilrig::mavlink::FindMessage(frame->message_id)) {
      std::cout << (first ? "\n" : ",\n") << FrameJson(*info, *frame, 0);
      first = false;
    }
  }
  const hilrig::mavlink::ParserCounters& c = parser.counters();
  std::cout << "\n], \"counters\": {\"frames_ok\": " << c.frames_ok
            << ", \"crc_failures\": " << c.crc_failures
            << ", \"bytes_skipped\": " << c.bytes_skipped
            << ", \"unknown_message_ids\": " << c.unknown_message_ids
            << ", \"bad_lengths\": " << c.bad_lengths
            << ", \"truncated_frames\": " << c.truncated_frames << "}}\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "tlog") return WriteTlog(argv[2]);
  if (argc == 3 && std::string(argv[1]) == "read") return ReadStream(argv[2]);
  std::cerr << "usage: mavlink_vectors tlog FILE | read FILE\n";
  return 2;
}
