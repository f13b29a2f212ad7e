// Writes the sample MCAP files the @mcap/core check reads (mcap_core_check.mjs): three channels,
// one with a JSON schema, one without and one of protobuf messages (hilrig.proto.Report, whose
// schema is a FileDescriptorSet with scenario.proto), 2000 small messages over several 16 KiB
// chunks, once zstd-compressed (OUT_DIR/zstd.mcap) and once stored (OUT_DIR/stored.mcap). Report
// number n has seed n and scenario "sample".
// Usage: mcap_sample_writer OUT_DIR
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "host/mcap/mcap_writer.h"
#include "host/mcap/protobuf_channel.h"
#include "proto/report.pb.h"

namespace {

using namespace hilrig::mcap;

constexpr int kMessages = 2000;

hilrig::rig::Result<void> WriteSample(const std::filesystem::path& path,
                                      ChunkCompression compression) {
  std::ofstream out(path, std::ios::binary);
  McapWriterOptions options;
  options.compression = compression;
  options.chunk_bytes = 16 << 10;
  McapWriter writer(out, options);
  if (auto opened = writer.Open("x-hilrig", "hilrig mcap_sample_writer"); !opened) return opened;
  const auto schema = writer.AddSchema(
      "hilrig.PlantState", "jsonschema",
      R"({"type":"object","properties":{"t_s":{"type":"number"},"z_m":{"type":"number"}}})");
  if (!schema.ok()) return schema.error();
  const auto state =
      writer.AddChannel(schema.value(), "/plant/state", "json", {{"rate_hz", "250"}});
  const auto events = writer.AddChannel(0, "/run/events", "json");
  const auto reports =
      AddProtobufChannel(writer, *hilrig::proto::Report::descriptor(), "/run/report");
  if (!state.ok() || !events.ok() || !reports.ok()) {
    return hilrig::rig::MakeError("AddChannel failed");
  }
  for (int i = 0; i < kMessages; ++i) {
    const bool event = i % 10 == 9;
    const bool report = i % 10 == 4;
    std::string payload = event ? R"({"event":"tick","n":)" + std::to_string(i / 10) + "}"
                                : R"({"t_s":)" + std::to_string(i * 0.004) + R"(,"z_m":)" +
                                      std::to_string(1.0 + 0.001 * (i % 100)) + "}";
    if (report) {
      hilrig::proto::Report sample;
      sample.set_scenario("sample");
      sample.set_seed(static_cast<std::uint64_t>(i / 10));
      sample.add_envelopes()->set_signal(hilrig::proto::GRASP_FORCE_N);
      payload = sample.SerializeAsString();
    }
    MessageToWrite message;
    message.channel_id = event ? events.value() : report ? reports.value() : state.value();
    message.sequence = static_cast<std::uint32_t>(i);
    message.log_time_ns = 1'000'000'000ull + 4'000'000ull * static_cast<std::uint64_t>(i);
    message.publish_time_ns = message.log_time_ns - 1000;
    message.payload = payload;
    if (auto written = writer.Write(message); !written) return written;
  }
  return writer.Close();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: mcap_sample_writer OUT_DIR\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  for (const auto& [name, compression] : {std::pair{"zstd.mcap", ChunkCompression::kZstd},
                                          std::pair{"stored.mcap", ChunkCompression::kNone}}) {
    if (auto written = WriteSample(dir / name, compression); !written) {
      std::fprintf(stderr, "mcap_sample_writer: %s: %s\n", name, written.error().message.c_str());
      return 1;
    }
  }
  return 0;
}
