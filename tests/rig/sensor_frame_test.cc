#include "rig/sensor_frame.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace hilrig::rig {
namespace {

MagneticSample Sample() {
  return {.node_id = 3,
          .x_code = 1200,
          .y_code = -3,
          .z_code = -32768,
          .sequence = 250,
          .status = kSensorStatusStale};
}

void ExpectRejected(const CanFrame& frame, const std::string& complaint) {
  const Result<MagneticSample> decoded = DecodeMagneticSample(frame);
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().message.find(complaint), std::string::npos) << decoded.error().message;
}

TEST(SensorFrameTest, RoundTrips) {
  const Result<MagneticSample> decoded = DecodeMagneticSample(EncodeMagneticSample(Sample()));

  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded.value(), Sample());
}

TEST(SensorFrameTest, LayoutIsLittleEndianThenSequenceAndStatus) {
  const CanFrame frame = EncodeMagneticSample(Sample());

  EXPECT_EQ(frame.id, 0x103u);
  EXPECT_EQ(std::vector<std::uint8_t>(frame.payload().begin(), frame.payload().end()),
            (std::vector<std::uint8_t>{0xB0, 0x04, 0xFD, 0xFF, 0x00, 0x80, 250, 0x04}));
}

TEST(SensorFrameTest, ReferenceNodeUsesId0x107) {
  MagneticSample sample = Sample();
  sample.node_id = kReferenceNodeId;

  EXPECT_EQ(EncodeMagneticSample(sample).id, 0x107u);
}

TEST(SensorFrameTest, RejectsIdBelowRange) {
  CanFrame frame = EncodeMagneticSample(Sample());
  frame.id = kSensorSampleBaseId;

  ExpectRejected(frame, "id 0x100 is outside");
}

TEST(SensorFrameTest, RejectsIdAboveRange) {
  CanFrame frame = EncodeMagneticSample(Sample());
  frame.id = 0x108;

  ExpectRejected(frame, "id 0x108 is outside");
}

TEST(SensorFrameTest, RejectsWrongLength) {
  CanFrame frame = EncodeMagneticSample(Sample());
  frame.length = 7;

  ExpectRejected(frame, "expected 8 bytes, got 7");
}

TEST(SensorFrameTest, RejectsExtendedFrame) {
  CanFrame frame = EncodeMagneticSample(Sample());
  frame.extended = true;

  ExpectRejected(frame, "extended");
}

TEST(SensorFrameTest, RejectsRemoteFrame) {
  ExpectRejected(CanFrame::Remote(0x103, 8, false), "remote");
}

TEST(SensorFrameTest, RejectsFdFrame) {
  CanFrame frame = EncodeMagneticSample(Sample());
  frame.fd = true;

  ExpectRejected(frame, "CAN FD");
}

TEST(SensorFrameTest, RejectsErrorFrame) {
  ExpectRejected(CanFrame::ErrorFrame(0x103, {}), "error frame");
}

TEST(SensorFrameDeathTest, EncodingNodeZeroAborts) {
  MagneticSample sample = Sample();
  sample.node_id = 0;

  EXPECT_DEATH(EncodeMagneticSample(sample), "node id");
}

}  // namespace
}  // namespace hilrig::rig
