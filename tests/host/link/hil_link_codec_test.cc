#include "host/link/hil_link_codec.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "tests/support/dut_inputs.h"

namespace hilrig::host {
namespace {

// Doubles that a decimal or float detour would change: the last bit must survive.
constexpr double kThird = 1.0 / 3.0;
const double kTiny = std::nextafter(0.0, 1.0);  // the smallest subnormal
const double kAlmostOne = std::nextafter(1.0, 0.0);

std::uint64_t Bits(double value) { return std::bit_cast<std::uint64_t>(value); }

void ExpectSameBits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  for (int i = 0; i < 3; ++i) EXPECT_EQ(Bits(a[i]), Bits(b[i])) << "component " << i;
}

// Decodes one complete frame; fails the test if anything else comes out.
proto::LinkMessage DecodeOne(const std::string& frame) {
  LinkDecoder decoder;
  decoder.Feed(frame);
  std::optional<LinkEvent> event = decoder.Next();
  EXPECT_TRUE(event.has_value());
  if (!event) return {};
  EXPECT_TRUE(std::holds_alternative<proto::LinkMessage>(*event))
      << std::get<LinkError>(*event).Message();
  if (!std::holds_alternative<proto::LinkMessage>(*event)) return {};
  return std::get<proto::LinkMessage>(*event);
}

std::string Frame(const proto::LinkMessage& message) { return EncodeLinkFrame(message).value(); }

proto::LinkMessage Bye(std::uint64_t sequence) {
  proto::LinkMessage message;
  message.mutable_bye()->mutable_header()->set_protocol_version(kHilLinkProtocolVersion);
  message.mutable_bye()->mutable_header()->set_sequence(sequence);
  return message;
}

// Every event the decoder yields for `bytes`, fed at once.
std::vector<LinkEvent> DecodeAll(LinkDecoder& decoder, const std::string& bytes) {
  decoder.Feed(bytes);
  std::vector<LinkEvent> events;
  while (auto event = decoder.Next()) events.push_back(std::move(*event));
  return events;
}

LinkErrorKind ErrorKind(const LinkEvent& event) {
  EXPECT_TRUE(std::holds_alternative<LinkError>(event));
  return std::holds_alternative<LinkError>(event) ? std::get<LinkError>(event).kind
                                                  : LinkErrorKind::kMalformed;
}

TEST(HilLinkCodecTest, ImuRoundTripsBitExact) {
  const ImuMessage sent{{0, 123'456'789}, {kThird, -kTiny, 1e300}, {kAlmostOne, -0.0, 9.81}};
  const proto::LinkMessage decoded = DecodeOne(Frame(ToLink(sent)));
  ASSERT_TRUE(decoded.has_imu());
  const ImuMessage received = std::get<ImuMessage>(DutInputFromLink(decoded).value());
  EXPECT_EQ(received.stamp.time_ns, 123'456'789);
  ExpectSameBits(received.gyro_rad_s, sent.gyro_rad_s);
  ExpectSameBits(received.accel_m_s2, sent.accel_m_s2);
}

TEST(HilLinkCodecTest, VioRoundTripsBitExact) {
  const VioMessage sent{{0, 5'000'000},
                        -2'000'000,
                        {kThird, 2 * kThird, -kTiny},
                        Eigen::Quaterniond(kAlmostOne, kThird, -kThird, kTiny)};
  const proto::LinkMessage decoded = DecodeOne(Frame(ToLink(sent)));
  ASSERT_TRUE(decoded.has_vio());
  const VioMessage received = std::get<VioMessage>(DutInputFromLink(decoded).value());
  EXPECT_EQ(received.capture_time_ns, -2'000'000);
  ExpectSameBits(received.position_m, sent.position_m);
  EXPECT_EQ(Bits(received.orientation.w()), Bits(kAlmostOne));
  EXPECT_EQ(Bits(received.orientation.x()), Bits(kThird));
  EXPECT_EQ(Bits(received.orientation.y()), Bits(-kThird));
  EXPECT_EQ(Bits(received.orientation.z()), Bits(kTiny));
}

TEST(HilLinkCodecTest, SetpointRoundTripsBitExact) {
  const SetpointMessage sent{
      {0, 1}, {1, 2, kThird}, {-kThird, 0, 0}, {0, kTiny, 0}, kAlmostOne, true, 2.5, kThird};
  const proto::LinkMessage decoded = DecodeOne(Frame(ToLink(sent)));
  ASSERT_TRUE(decoded.has_setpoint());
  const SetpointMessage received = std::get<SetpointMessage>(DutInputFromLink(decoded).value());
  ExpectSameBits(received.position_m, sent.position_m);
  ExpectSameBits(received.velocity_m_s, sent.velocity_m_s);
  ExpectSameBits(received.acceleration_m_s2, sent.acceleration_m_s2);
  EXPECT_EQ(Bits(received.yaw_rad), Bits(kAlmostOne));
  EXPECT_TRUE(received.grasp_regulate);
  EXPECT_EQ(received.grasp_force_n, 2.5);
  EXPECT_EQ(Bits(received.grasp_reference_angle_rad), Bits(kThird));
}

TEST(HilLinkCodecTest, ActuatorCommandRoundTripsBitExact) {
  ActuatorMessage sent;
  sent.stamp = {0, 42'000'000};
  sent.answers_sequence = 42;
  sent.rotor_thrust_n = {kThird, 2.0, kAlmostOne, kTiny};
  sent.armed = true;
  sent.estimated_position_m = {kThird, -kThird, 1};
  for (int i = 0; i < 6; ++i) sent.tactile_force_sensor_n[i] = {i * kThird, -i * 1.0, kTiny};
  sent.tactile_ready = true;
  sent.servo_angle_rad = 1.2345678901234567;
  sent.grasp_force_estimate_n = kThird;
  sent.external_force_world_n = {0, 0, -kAlmostOne};
  const proto::LinkMessage decoded = DecodeOne(Frame(ToLink(sent)));
  ASSERT_TRUE(decoded.has_command());
  const ActuatorMessage received = FromLink(decoded.command()).value();
  EXPECT_EQ(received.stamp.time_ns, 42'000'000);
  EXPECT_EQ(received.answers_sequence, 42u);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(Bits(received.rotor_thrust_n[i]), Bits(sent.rotor_thrust_n[i]));
  EXPECT_TRUE(received.armed);
  ExpectSameBits(received.estimated_position_m, sent.estimated_position_m);
  for (int i = 0; i < 6; ++i) {
    ExpectSameBits(received.tactile_force_sensor_n[i], sent.tactile_force_sensor_n[i]);
  }
  EXPECT_TRUE(received.tactile_ready);
  EXPECT_EQ(Bits(received.servo_angle_rad), Bits(1.2345678901234567));
  EXPECT_EQ(Bits(received.grasp_force_estimate_n), Bits(kThird));
  ExpectSameBits(received.external_force_world_n, sent.external_force_world_n);
}

// A caller that keeps one message per stream (the run's log) fills it again and again: each fill
// gives what a fresh conversion gives, whatever the message held before.
TEST(HilLinkCodecTest, FillingAKeptMessageEqualsAFreshConversion) {
  proto::LinkMessage kept;
  ImuMessage imu;
  imu.stamp = {3, 4'000'000};
  imu.gyro_rad_s = {kThird, 0, -1};
  FillLink(DutInput(VioMessage{}), kept);
  FillLink(DutInput(imu), kept);
  EXPECT_EQ(kept.SerializeAsString(), ToLink(DutInput(imu)).SerializeAsString());

  ActuatorMessage command;
  command.rotor_thrust_n = {1, 2, 3, 4};
  command.tactile_force_sensor_n[5] = {kThird, 0, 0};
  proto::ActuatorCommand kept_command;
  FillLink(command, kept_command);
  command.rotor_thrust_n = {5, 6, 7, 8};
  FillLink(command, kept_command);
  EXPECT_EQ(kept_command.rotor_thrust_n_size(), 4);
  EXPECT_EQ(kept_command.tactile_force_sensor_n_size(), 6);
  EXPECT_EQ(kept_command.SerializeAsString(), ToLink(command).command().SerializeAsString());
}

TEST(HilLinkCodecTest, EachInputStreamTravelsInTheFieldOfItsName) {
  for (std::size_t index = 0; index < kDutInputStreams; ++index) {
    const google::protobuf::FieldDescriptor& field = DutInputPayloadField(index);
    EXPECT_EQ(field.name(), DutInputStream(index));
    EXPECT_EQ(field.containing_oneof()->name(), "payload");
  }
}

TEST(HilLinkCodecTest, HelloStepAndByeRoundTrip) {
  LinkSequencer sequencer;
  proto::LinkMessage hello;
  hello.mutable_hello()->set_role(proto::Hello::DUT);
  hello.mutable_hello()->set_name("dut");
  sequencer.Stamp(hello, 0);
  proto::LinkMessage step;
  step.mutable_step()->set_tick(3);
  step.mutable_step()->set_now_ns(3'000'000);
  step.mutable_step()->set_can_frames_sent(1);
  step.mutable_step()->add_can_frame_time_ns(2'999'000);
  sequencer.Stamp(step, 3'000'000);
  proto::LinkMessage bye;
  bye.mutable_bye()->set_error(true);
  bye.mutable_bye()->set_reason("because");
  sequencer.Stamp(bye, 0);
  LinkDecoder decoder;
  const std::vector<LinkEvent> events = DecodeAll(decoder, Frame(hello) + Frame(step) + Frame(bye));
  ASSERT_EQ(events.size(), 3u);
  const auto& got_hello = std::get<proto::LinkMessage>(events[0]).hello();
  EXPECT_EQ(got_hello.role(), proto::Hello::DUT);
  EXPECT_EQ(got_hello.name(), "dut");
  const auto& got_step = std::get<proto::LinkMessage>(events[1]).step();
  EXPECT_EQ(got_step.tick(), 3u);
  EXPECT_EQ(got_step.can_frame_time_ns(0), 2'999'000);
  EXPECT_EQ(got_step.header().time_ns(), 3'000'000);
  EXPECT_EQ(std::get<proto::LinkMessage>(events[2]).bye().reason(), "because");
  EXPECT_EQ(decoder.counters().messages, 3u);
}

TEST(HilLinkCodecTest, FrameIsVarintLengthThenMessage) {
  const proto::LinkMessage message = Bye(0);
  const std::string frame = Frame(message);
  const std::size_t size = message.ByteSizeLong();
  ASSERT_LT(size, 128u);  // one varint byte
  ASSERT_EQ(frame.size(), size + 1);
  EXPECT_EQ(static_cast<std::size_t>(frame[0]), size);
}

TEST(HilLinkCodecTest, DecodesAFrameFedOneByteAtATime) {
  const std::string frame = Frame(ToLink(ImuMessage{{0, 1}, {1, 2, 3}, {4, 5, 6}}));
  LinkDecoder decoder;
  for (std::size_t i = 0; i + 1 < frame.size(); ++i) {
    decoder.Feed(frame.substr(i, 1));
    EXPECT_FALSE(decoder.Next().has_value()) << "after byte " << i;
  }
  decoder.Feed(frame.substr(frame.size() - 1));
  const std::optional<LinkEvent> event = decoder.Next();
  ASSERT_TRUE(event.has_value());
  EXPECT_EQ(std::get<proto::LinkMessage>(*event).imu().accel_m_s2().z(), 6.0);
}

TEST(HilLinkCodecTest, DecodesFramesSplitAcrossChunksAtOddPlaces) {
  std::string stream;
  for (std::uint64_t i = 0; i < 5; ++i) stream += Frame(ToLink(ImuMessage{{i, 0}}));
  LinkDecoder decoder;
  std::vector<std::uint64_t> sequences;
  for (std::size_t at = 0; at < stream.size(); at += 7) {  // 7 divides no frame size here
    decoder.Feed(stream.substr(at, 7));
    while (auto event = decoder.Next()) {
      sequences.push_back(std::get<proto::LinkMessage>(*event).imu().header().sequence());
    }
  }
  EXPECT_EQ(sequences, (std::vector<std::uint64_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(decoder.buffered_bytes(), 0u);
}

TEST(HilLinkCodecTest, OversizedLengthIsANamedErrorAndStopsTheStream) {
  LinkDecoder decoder(64);
  // Varint 4097, then a valid frame that must not be delivered any more.
  const std::vector<LinkEvent> events =
      DecodeAll(decoder, std::string("\x81\x20", 2) + Frame(Bye(0)));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(ErrorKind(events[0]), LinkErrorKind::kOversized);
  EXPECT_EQ(decoder.counters().oversized, 1u);
  EXPECT_TRUE(decoder.broken());
  decoder.Feed(Frame(Bye(1)));
  EXPECT_FALSE(decoder.Next().has_value());
}

TEST(HilLinkCodecTest, EncoderRefusesAMessageOverTheLimit) {
  proto::LinkMessage message = Bye(0);
  message.mutable_bye()->set_reason(std::string(kMaxLinkMessageBytes, 'x'));
  const auto frame = EncodeLinkFrame(message);
  ASSERT_FALSE(frame.ok());
  EXPECT_NE(frame.error().message.find("4096-byte limit"), std::string::npos);
}

TEST(HilLinkCodecTest, GarbageIsMalformed) {
  LinkDecoder decoder;
  // Length 4, then a field with wire type 7, which protobuf does not have.
  const std::vector<LinkEvent> events = DecodeAll(decoder, std::string("\x04\x0f\xff\xff\xff", 5));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(ErrorKind(events[0]), LinkErrorKind::kMalformed);
  EXPECT_EQ(decoder.counters().malformed, 1u);
}

TEST(HilLinkCodecTest, OverlongLengthPrefixIsMalformed) {
  LinkDecoder decoder(1u << 30);
  // Eleven continuation bytes of zero value: no varint is that long.
  const std::vector<LinkEvent> events = DecodeAll(decoder, std::string(11, '\x80'));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(ErrorKind(events[0]), LinkErrorKind::kMalformed);
}

TEST(HilLinkCodecTest, MessageWithoutPayloadIsMalformed) {
  LinkDecoder decoder;
  const std::vector<LinkEvent> events = DecodeAll(decoder, std::string("\x00", 1));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(ErrorKind(events[0]), LinkErrorKind::kMalformed);
}

TEST(HilLinkCodecTest, OtherProtocolVersionIsBadVersion) {
  proto::LinkMessage message = Bye(0);
  message.mutable_bye()->mutable_header()->set_protocol_version(2);
  LinkDecoder decoder;
  const std::vector<LinkEvent> events = DecodeAll(decoder, Frame(message));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(ErrorKind(events[0]), LinkErrorKind::kBadVersion);
  EXPECT_NE(std::get<LinkError>(events[0]).detail.find("protocol version 2"), std::string::npos);
  EXPECT_EQ(decoder.counters().bad_version, 1u);
  EXPECT_EQ(decoder.counters().messages, 0u);
}

TEST(HilLinkCodecTest, RepeatedSequenceIsDuplicate) {
  LinkDecoder decoder;
  const std::vector<LinkEvent> events =
      DecodeAll(decoder, Frame(Bye(0)) + Frame(Bye(1)) + Frame(Bye(1)));
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(ErrorKind(events[2]), LinkErrorKind::kDuplicate);
  EXPECT_EQ(decoder.counters().duplicates, 1u);
  EXPECT_EQ(decoder.counters().messages, 2u);
}

TEST(HilLinkCodecTest, OlderSequenceIsOutOfOrder) {
  LinkDecoder decoder;
  const std::vector<LinkEvent> events =
      DecodeAll(decoder, Frame(Bye(0)) + Frame(Bye(1)) + Frame(Bye(2)) + Frame(Bye(0)));
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(ErrorKind(events[3]), LinkErrorKind::kOutOfOrder);
  EXPECT_EQ(decoder.counters().out_of_order, 1u);
}

TEST(HilLinkCodecTest, SkippedSequenceIsAGapAndTheStreamResynchronises) {
  LinkDecoder decoder;
  const std::vector<LinkEvent> events =
      DecodeAll(decoder, Frame(Bye(0)) + Frame(Bye(3)) + Frame(Bye(4)));
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(ErrorKind(events[1]), LinkErrorKind::kSequenceGap);
  ASSERT_TRUE(std::holds_alternative<proto::LinkMessage>(events[2]));  // 4 follows 3
  EXPECT_EQ(decoder.counters().sequence_gaps, 1u);
  EXPECT_EQ(decoder.counters().messages, 2u);
}

TEST(HilLinkCodecTest, StreamsAreSequencedIndependently) {
  LinkDecoder decoder;
  const std::vector<LinkEvent> events =
      DecodeAll(decoder, Frame(Bye(0)) + Frame(ToLink(ImuMessage{{0, 0}})) + Frame(Bye(1)));
  ASSERT_EQ(events.size(), 3u);
  for (const LinkEvent& event : events)
    EXPECT_TRUE(std::holds_alternative<proto::LinkMessage>(event));
}

TEST(HilLinkCodecTest, CommandWithWrongRotorCountIsRefused) {
  proto::LinkMessage message = ToLink(ActuatorMessage{});
  message.mutable_command()->add_rotor_thrust_n(1.0);  // a fifth rotor
  const auto command = FromLink(message.command());
  ASSERT_FALSE(command.ok());
  EXPECT_NE(command.error().message.find("5 rotor thrusts"), std::string::npos);
}

TEST(HilLinkCodecTest, CounterMetricsAreNamedWithThePrefix) {
  LinkCounters counters;
  counters.duplicates = 3;
  const auto metrics = LinkCounterMetrics(counters, "link_rx_");
  bool found = false;
  for (const auto& [name, value, unit] : metrics) {
    if (name == "link_rx_duplicates") {
      found = true;
      EXPECT_EQ(value, 3.0);
    }
  }
  EXPECT_TRUE(found);
}

TEST(HilLinkCodecTest, ErrorNamesAreTheDocumentedOnes) {
  EXPECT_STREQ(LinkErrorName(LinkErrorKind::kOversized), "oversized");
  EXPECT_STREQ(LinkErrorName(LinkErrorKind::kMalformed), "malformed");
  EXPECT_STREQ(LinkErrorName(LinkErrorKind::kBadVersion), "bad_version");
  EXPECT_STREQ(LinkErrorName(LinkErrorKind::kSequenceGap), "sequence_gap");
  EXPECT_STREQ(LinkErrorName(LinkErrorKind::kDuplicate), "duplicate");
  EXPECT_STREQ(LinkErrorName(LinkErrorKind::kOutOfOrder), "out_of_order");
}

// What the peer did wrong survives as a code of the rig::Error that carries it up the layers.
TEST(HilLinkCodecTest, EveryErrorKindSurvivesARigError) {
  for (const LinkErrorKind kind :
       {LinkErrorKind::kOversized, LinkErrorKind::kMalformed, LinkErrorKind::kBadVersion,
        LinkErrorKind::kSequenceGap, LinkErrorKind::kDuplicate, LinkErrorKind::kOutOfOrder}) {
    const rig::Error error = LinkProtocolError(kind, "dut sent a bad message");
    EXPECT_EQ(error.code, rig::ErrorCode::kLinkProtocol);
    EXPECT_EQ(error.message, "dut sent a bad message");
    EXPECT_EQ(LinkErrorKindOf(error), kind) << LinkErrorName(kind);
    EXPECT_EQ(LinkErrorKindOf(rig::InContext("run: ", error)), kind) << LinkErrorName(kind);
  }
}

TEST(HilLinkCodecTest, AnErrorOfAnotherCodeHasNoLinkKind) {
  EXPECT_EQ(LinkErrorKindOf(rig::MakeError("malformed: bytes")), std::nullopt);
  rig::Error timeout = rig::MakeError(rig::ErrorCode::kTimeout, "no answer");
  timeout.subcode = static_cast<int>(LinkErrorKind::kDuplicate);
  EXPECT_EQ(LinkErrorKindOf(timeout), std::nullopt);
}

// A message of every field set to a value whose last bit a detour would change. A new DutInput
// alternative needs an overload here for the tests below to compile.
void Fill(ImuMessage& m) {
  m.gyro_rad_s = {kThird, -kTiny, kAlmostOne};
  m.accel_m_s2 = {-kThird, 9.81, kTiny};
  m.gyro_clipped = true;
  m.accel_clipped = true;
}
void Fill(VioMessage& m) {
  m.capture_time_ns = -7;
  m.position_m = {kThird, kTiny, -kAlmostOne};
  m.orientation = Eigen::Quaterniond(kAlmostOne, kThird, -kTiny, 0.25);
}
void Fill(SetpointMessage& m) {
  m.position_m = {kThird, 2, 3};
  m.velocity_m_s = {kTiny, -kTiny, 1};
  m.acceleration_m_s2 = {kAlmostOne, 0, -kThird};
  m.yaw_rad = -kThird;
  m.grasp_regulate = true;
  m.grasp_force_n = kAlmostOne;
  m.grasp_reference_angle_rad = kTiny;
}
void Fill(MagnetometerMessage& m) { m.field_body_t = {kTiny, -kThird * 1e-4, kAlmostOne * 1e-4}; }
void Fill(BarometerMessage& m) {
  m.pressure_pa = 101325 - kThird;
  m.temperature_c = kAlmostOne;
}
void Fill(GnssMessage& m) {
  m.latitude_deg = 47 + kThird;
  m.longitude_deg = -kAlmostOne;
  m.altitude_m = 408 + kTiny;
  m.velocity_m_s = {kThird, -kTiny, kAlmostOne};
  m.horizontal_accuracy_m = kThird;
  m.vertical_accuracy_m = kAlmostOne;
  m.satellites = 255;
}

// Alternative `index` of DutInput with every field set, the first of its stream, stamped with a
// time that names the index.
DutInput FilledInput(std::size_t index) {
  DutInput input = test::DutInputAt(index);
  std::visit(
      [index](auto& message) {
        Fill(message);
        message.stamp = {0, 1'000'000'007 + static_cast<std::int64_t>(index)};
      },
      input);
  return input;
}

TEST(HilLinkCodecTest, EveryDutInputRoundTripsBitExactThroughTheLink) {
  for (std::size_t index = 0; index < kDutInputStreams; ++index) {
    SCOPED_TRACE(DutInputStream(index));
    const DutInput sent = FilledInput(index);
    const proto::LinkMessage link = ToLink(sent);
    // The wire names the stream as the report does.
    ASSERT_NE(link.payload_case(), proto::LinkMessage::PAYLOAD_NOT_SET);
    EXPECT_EQ(proto::LinkMessage::descriptor()->FindFieldByNumber(link.payload_case())->name(),
              DutInputStream(index));
    const std::optional<DutInput> received = DutInputFromLink(DecodeOne(Frame(link)));
    ASSERT_TRUE(received.has_value());
    EXPECT_EQ(received->index(), index);
    EXPECT_EQ(StampOf(*received).time_ns, 1'000'000'007 + static_cast<std::int64_t>(index));
    // Serialization writes doubles bit for bit, so equal bytes mean every field survived.
    EXPECT_EQ(ToLink(*received).SerializeAsString(), link.SerializeAsString());
  }
}

// The sequencer and decoder keep one slot per payload field number.
TEST(HilLinkCodecTest, EveryPayloadHasASequenceSlot) {
  const google::protobuf::OneofDescriptor* payload =
      proto::LinkMessage::descriptor()->FindOneofByName("payload");
  ASSERT_NE(payload, nullptr);
  for (int i = 0; i < payload->field_count(); ++i) {
    EXPECT_LT(static_cast<std::size_t>(payload->field(i)->number()), kLinkPayloadSlots)
        << payload->field(i)->name();
  }
}

TEST(HilLinkCodecTest, OtherPayloadsAreNoDutInput) {
  proto::LinkMessage message;
  EXPECT_FALSE(DutInputFromLink(message).has_value());
  EXPECT_FALSE(DutInputFromLink(Bye(0)).has_value());
  message.mutable_step()->set_tick(3);
  EXPECT_FALSE(DutInputFromLink(message).has_value());
  EXPECT_FALSE(DutInputFromLink(ToLink(ActuatorMessage{})).has_value());
  message.mutable_hello()->set_name("x");
  EXPECT_FALSE(DutInputFromLink(message).has_value());
}

TEST(HilLinkCodecTest, EveryDutInputHasItsOwnLastTakenSequenceField) {
  const google::protobuf::Descriptor* command = proto::ActuatorCommand::descriptor();
  for (std::size_t index = 0; index < kDutInputStreams; ++index) {
    SCOPED_TRACE(DutInputStream(index));
    proto::ActuatorCommand answer;
    EXPECT_FALSE(LastTakenSequence(answer, index).has_value());
    SetLastTakenSequence(answer, index, 40 + index);
    EXPECT_EQ(LastTakenSequence(answer, index), 40 + index);
    // The field is the stream's own: last_<stream>_sequence, and no other stream reads it.
    const std::string field = "last_" + std::string(DutInputStream(index)) + "_sequence";
    ASSERT_NE(command->FindFieldByName(field), nullptr) << field;
    EXPECT_TRUE(answer.GetReflection()->HasField(answer, command->FindFieldByName(field)));
    for (std::size_t other = 0; other < kDutInputStreams; ++other) {
      if (other == index) continue;
      EXPECT_FALSE(LastTakenSequence(answer, other).has_value()) << DutInputStream(other);
    }
  }
}

}  // namespace
}  // namespace hilrig::host
