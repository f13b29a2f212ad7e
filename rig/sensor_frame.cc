#include "rig/sensor_frame.h"

#include <array>
#include <cstdio>
#include <string>

#include "rig/check.h"

namespace hilrig::rig {
namespace {

constexpr std::size_t kSampleLength = 8;

bool IsSensorNode(std::uint32_t node_id) {
  return node_id >= kFirstTactileNodeId && node_id <= kReferenceNodeId;
}

void PutInt16Le(std::int16_t value, std::uint8_t* out) {
  const auto bits = static_cast<std::uint16_t>(value);
  out[0] = static_cast<std::uint8_t>(bits & 0xFF);
  out[1] = static_cast<std::uint8_t>(bits >> 8);
}

std::int16_t GetInt16Le(const std::uint8_t* in) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(in[0] | (in[1] << 8)));
}

Result<void> CheckSampleFrameKind(const CanFrame& frame) {
  if (frame.error) return MakeError("sensor sample: error frame, not a sample");
  if (frame.remote) return MakeError("sensor sample: remote frame carries no sample");
  if (frame.fd) return MakeError("sensor sample: expected a classic frame, got CAN FD");
  if (frame.extended) return MakeError("sensor sample: expected an 11-bit id, got extended");
  if (frame.id <= kSensorSampleBaseId || !IsSensorNode(frame.id - kSensorSampleBaseId)) {
    char message[96];
    std::snprintf(message, sizeof(message),
                  "sensor sample: id 0x%X is outside the sample ids 0x%X..0x%X",
                  static_cast<unsigned>(frame.id), kSensorSampleBaseId + kFirstTactileNodeId,
                  kSensorSampleBaseId + kReferenceNodeId);
    return MakeError(message);
  }
  if (frame.length != kSampleLength) {
    return MakeError("sensor sample: expected 8 bytes, got " + std::to_string(frame.length));
  }
  return {};
}

}  // namespace

CanFrame EncodeMagneticSample(const MagneticSample& sample) {
  HILRIG_CHECK(IsSensorNode(sample.node_id), "sensor node id must be 1..7");
  std::array<std::uint8_t, kSampleLength> bytes{};
  PutInt16Le(sample.x_code, &bytes[0]);
  PutInt16Le(sample.y_code, &bytes[2]);
  PutInt16Le(sample.z_code, &bytes[4]);
  bytes[6] = sample.sequence;
  bytes[7] = sample.status;
  return CanFrame::Classic(kSensorSampleBaseId + sample.node_id, bytes);
}

Result<MagneticSample> DecodeMagneticSample(const CanFrame& frame) {
  if (Result<void> kind = CheckSampleFrameKind(frame); !kind) return kind.error();
  MagneticSample sample;
  sample.node_id = static_cast<std::uint8_t>(frame.id - kSensorSampleBaseId);
  sample.x_code = GetInt16Le(&frame.data[0]);
  sample.y_code = GetInt16Le(&frame.data[2]);
  sample.z_code = GetInt16Le(&frame.data[4]);
  sample.sequence = frame.data[6];
  sample.status = frame.data[7];
  return sample;
}

}  // namespace hilrig::rig
