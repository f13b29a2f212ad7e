#include "rig/sensor_frame.h"

namespace hilrig::rig {

CanFrame EncodeMagneticSample(const MagneticSample& sample) {
  TactileSample tactile;
  tactile.node_id = sample.node_id;
  tactile.code = {static_cast<std::uint16_t>(sample.x_code),
                  static_cast<std::uint16_t>(sample.y_code),
                  static_cast<std::uint16_t>(sample.z_code)};
  tactile.sequence = sample.sequence;
  tactile.status = sample.status;
  return EncodeTactileSample(tactile);
}

Result<MagneticSample> DecodeMagneticSample(const CanFrame& frame) {
  Result<TactileSample> decoded = DecodeTactileSample(frame);
  if (!decoded) return decoded.error();
  const TactileSample& tactile = decoded.value();
  MagneticSample sample;
  sample.node_id = tactile.node_id;
  sample.x_code = static_cast<std::int16_t>(tactile.code[0]);
  sample.y_code = static_cast<std::int16_t>(tactile.code[1]);
  sample.z_code = static_cast<std::int16_t>(tactile.code[2]);
  sample.sequence = tactile.sequence;
  sample.status = tactile.status;
  return sample;
}

}  // namespace hilrig::rig
