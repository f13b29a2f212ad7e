// A file McapWriter writes for the tests: three channels on two schemas, `messages` messages in
// turn on each with payloads of varied length, so that small chunks make many of them.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "host/mcap/mcap_writer.h"
#include "rig/check.h"

namespace hilrig::mcap::testing {

inline std::string PayloadOf(std::size_t i) {
  return "{\"i\":" + std::to_string(i) + ",\"pad\":\"" + std::string(i % 37, 'a' + i % 26) + "\"}";
}

inline MessageToWrite NthMessage(std::size_t i, const std::string& payload) {
  return MessageToWrite{.channel_id = static_cast<std::uint16_t>(i % 3),
                        .sequence = static_cast<std::uint32_t>(i / 3),
                        .log_time_ns = 1'000'000'000ull + 1'000'000ull * i,
                        .publish_time_ns = 999'000'000ull + 1'000'000ull * i,
                        .payload = payload};
}

inline std::string WriteTestFile(std::size_t messages, McapWriterOptions options) {
  std::ostringstream out;
  McapWriter writer(out, options);
  HILRIG_CHECK(writer.Open("x-hilrig", "hilrig test").ok(), "Open");
  const std::uint16_t state =
      writer.AddSchema("State", "jsonschema", "{\"type\":\"object\"}").value();
  const std::uint16_t event = writer.AddSchema("Event", "jsonschema", "{}").value();
  HILRIG_CHECK(writer.AddChannel(state, "/plant/state", "json", {{"rate_hz", "250"}}).ok(), "0");
  HILRIG_CHECK(writer.AddChannel(event, "/run/events", "json").ok(), "1");
  HILRIG_CHECK(writer.AddChannel(0, "/dut/raw", "").ok(), "2");
  for (std::size_t i = 0; i < messages; ++i) {
    const std::string payload = PayloadOf(i);
    HILRIG_CHECK(writer.Write(NthMessage(i, payload)).ok(), "Write");
  }
  HILRIG_CHECK(writer.Close().ok(), "Close");
  return out.str();
}

}  // namespace hilrig::mcap::testing
