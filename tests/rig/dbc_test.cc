#include "rig/dbc.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>

#include "tests/support/test_paths.h"

namespace hilrig::rig {
namespace {

constexpr const char* kDbc = R"(VERSION ""

NS_ :
	CM_

BS_:

BU_: Ecu Tool

BO_ 2148532225 Motor: 8 Ecu
 SG_ Speed : 7|16@0+ (0.5,-100) [-100|32667.5] "rpm" Tool
 SG_ Torque : 16|12@1- (0.1,0) [-204.8|204.7] "N.m" Tool,Ecu
 SG_ Mode M : 56|4@1+ (1,0) [0|15] "" Tool
 SG_ Extra m2 : 60|4@1+ (1,0) [0|15] "" Tool

CM_ BO_ 2148532225 "a comment that the parser skips";
)";

DbcDatabase Parse(const std::string& text) {
  Result<DbcDatabase> parsed = ParseDbc(text);
  EXPECT_TRUE(parsed.ok()) << parsed.error().message;
  return parsed.ok() ? std::move(parsed).value() : DbcDatabase{};
}

TEST(DbcTest, ReadsNodesMessagesAndSignals) {
  const DbcDatabase database = Parse(kDbc);

  ASSERT_EQ(database.messages.size(), 1u);
  const DbcMessage& message = database.messages[0];
  EXPECT_EQ(database.nodes, (std::vector<std::string>{"Ecu", "Tool"}));
  EXPECT_EQ(message.id, 0x100001u);
  EXPECT_TRUE(message.extended);
  EXPECT_EQ(message.name, "Motor");
  EXPECT_EQ(message.length_bytes, 8u);
  EXPECT_EQ(message.transmitter, "Ecu");
  ASSERT_EQ(message.signals.size(), 4u);
  const DbcSignal& torque = message.signals[1];
  EXPECT_EQ(torque.start_bit, 16u);
  EXPECT_EQ(torque.length_bits, 12u);
  EXPECT_TRUE(torque.little_endian);
  EXPECT_TRUE(torque.is_signed);
  EXPECT_DOUBLE_EQ(torque.factor, 0.1);
  EXPECT_DOUBLE_EQ(torque.minimum, -204.8);
  EXPECT_EQ(torque.unit, "N.m");
  EXPECT_EQ(torque.receivers, (std::vector<std::string>{"Tool", "Ecu"}));
  EXPECT_TRUE(message.signals[2].is_multiplexor);
  EXPECT_EQ(message.signals[3].multiplex_value, std::optional<std::uint32_t>(2));
}

TEST(DbcTest, ExtractsMotorolaSignalFromItsMsb) {
  const DbcDatabase database = Parse(kDbc);
  const std::array<std::uint8_t, 8> payload = {0x12, 0x34, 0, 0, 0, 0, 0, 0};

  const Result<std::int64_t> raw =
      ExtractRawSignal(*database.messages[0].FindSignal("Speed"), payload);

  ASSERT_TRUE(raw.ok()) << raw.error().message;
  EXPECT_EQ(raw.value(), 0x1234);
  EXPECT_DOUBLE_EQ(database.messages[0].FindSignal("Speed")->ToPhysical(raw.value()),
                   0x1234 * 0.5 - 100);
}

TEST(DbcTest, SignExtendsSignedIntelSignal) {
  const DbcDatabase database = Parse(kDbc);
  const std::array<std::uint8_t, 8> payload = {0, 0, 0xFE, 0x0F, 0, 0, 0, 0};  // 12-bit -2

  const Result<std::int64_t> raw =
      ExtractRawSignal(*database.messages[0].FindSignal("Torque"), payload);

  ASSERT_TRUE(raw.ok()) << raw.error().message;
  EXPECT_EQ(raw.value(), -2);
}

TEST(DbcTest, SignalPastTheShortPayloadIsAnError) {
  const DbcDatabase database = Parse(kDbc);
  const std::array<std::uint8_t, 2> payload = {0, 0};

  const Result<std::int64_t> raw =
      ExtractRawSignal(*database.messages[0].FindSignal("Torque"), payload);

  ASSERT_FALSE(raw.ok());
  EXPECT_NE(raw.error().message.find("reaches past the 2-byte payload"), std::string::npos);
}

TEST(DbcTest, MalformedSignalNamesItsLine) {
  const Result<DbcDatabase> parsed = ParseDbc("BO_ 1 M: 8 X\n SG_ S : 0|8@2+ (1,0) [0|1] \"\" X\n");

  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.error().message.find("dbc line 2: SG_ byte order"), std::string::npos)
      << parsed.error().message;
}

TEST(DbcTest, SignalOutsideAMessageIsAnError) {
  const Result<DbcDatabase> parsed = ParseDbc(" SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n");

  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.error().message.find("SG_ outside a BO_"), std::string::npos);
}

TEST(DbcTest, MissingFileIsAnError) {
  const Result<DbcDatabase> loaded = LoadDbcFile("/nonexistent/tactile.dbc");

  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().message.find("cannot read"), std::string::npos);
}

TEST(DbcTest, AFolderIsRefusedNotReadAsAnEmptyDatabase) {
  const std::string folder = ::hilrig::test_support::SourceDir() + "/proto";
  const Result<DbcDatabase> loaded = LoadDbcFile(folder);
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().message.find("cannot read " + folder + ": a folder"), std::string::npos)
      << loaded.error().message;
}

}  // namespace
}  // namespace hilrig::rig
