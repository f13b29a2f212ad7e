// proto/tactile.dbc is what CAN tools (SavvyCAN, cantools, CANdb++) use to read the tactile bus;
// rig/tactile_protocol.cc is what the rig uses. These tests encode random messages with the codec
// and read them back through the DBC's signal definitions, for every message kind and node, so the
// two statements of the layout cannot drift apart.
#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <random>
#include <string>

#include "rig/dbc.h"
#include "rig/tactile_protocol.h"
#include "tests/support/test_paths.h"

namespace hilrig::rig {
namespace {

using SignalValues = std::map<std::string, double>;

const DbcDatabase& Database() {
  static const DbcDatabase database = [] {
    Result<DbcDatabase> loaded =
        LoadDbcFile(::hilrig::test_support::SourceDir() + "/proto/tactile.dbc");
    HILRIG_CHECK(loaded.ok(), loaded.ok() ? "" : loaded.error().message);
    return std::move(loaded).value();
  }();
  return database;
}

const DbcMessage& Message(std::uint32_t id) {
  const DbcMessage* message = Database().FindMessage(id);
  HILRIG_CHECK(message != nullptr, "message missing from tactile.dbc");
  return *message;
}

// Every signal of `frame` that the DBC says is present (multiplexed ones only when selected),
// in physical units, after checking it lies in the DBC's declared range.
SignalValues ReadSignals(const DbcMessage& message, const CanFrame& frame) {
  SignalValues values;
  std::optional<std::int64_t> selector;
  for (const DbcSignal& signal : message.signals) {
    if (!signal.is_multiplexor) continue;
    const Result<std::int64_t> raw = ExtractRawSignal(signal, frame.payload());
    EXPECT_TRUE(raw.ok()) << raw.error().message;
    if (raw.ok()) selector = raw.value();
  }
  for (const DbcSignal& signal : message.signals) {
    if (signal.multiplex_value &&
        std::optional<std::int64_t>(*signal.multiplex_value) != selector) {
      continue;
    }
    const Result<std::int64_t> raw = ExtractRawSignal(signal, frame.payload());
    if (!raw.ok()) {
      ADD_FAILURE() << message.name << "." << signal.name << ": " << raw.error().message;
      continue;
    }
    const double physical = signal.ToPhysical(raw.value());
    EXPECT_GE(physical, signal.minimum - 1e-9) << message.name << "." << signal.name;
    EXPECT_LE(physical, signal.maximum + 1e-9) << message.name << "." << signal.name;
    values[signal.name] = physical;
  }
  return values;
}

void ExpectSignals(const SignalValues& actual, const SignalValues& expected,
                   const std::string& context) {
  EXPECT_EQ(actual.size(), expected.size()) << context;
  for (const auto& [name, value] : expected) {
    const auto it = actual.find(name);
    if (it == actual.end()) {
      ADD_FAILURE() << context << ": DBC has no signal " << name;
      continue;
    }
    EXPECT_NEAR(it->second, value, 1e-9) << context << ": " << name;
  }
}

double Bit(std::uint8_t bits, std::uint8_t mask) { return (bits & mask) != 0 ? 1.0 : 0.0; }

TEST(TactileDbcTest, ListsHostAndSevenNodes) {
  EXPECT_EQ(Database().nodes, (std::vector<std::string>{"Host", "Node1", "Node2", "Node3", "Node4",
                                                        "Node5", "Node6", "Node7"}));
}

TEST(TactileDbcTest, HasOneMessagePerNodeAndKindAndNothingElse) {
  for (std::uint8_t node = tactile_bus::kFirstNodeId; node <= tactile_bus::kReferenceNodeId;
       ++node) {
    const std::string suffix = "_N" + std::to_string(node);
    const std::string transmitter = "Node" + std::to_string(node);
    EXPECT_EQ(Message(tactile_bus::kSampleBaseId + node).name, "TactileSample" + suffix);
    EXPECT_EQ(Message(tactile_bus::kSampleBaseId + node).transmitter, transmitter);
    EXPECT_EQ(Message(tactile_bus::kStatusBaseId + node).name, "TactileStatus" + suffix);
    EXPECT_EQ(Message(tactile_bus::kStatusBaseId + node).transmitter, transmitter);
    EXPECT_EQ(Message(tactile_bus::kConfigBaseId + node).name, "TactileConfig" + suffix);
    EXPECT_EQ(Message(tactile_bus::kConfigBaseId + node).transmitter, "Host");
  }
  EXPECT_EQ(Message(tactile_bus::kConfigBaseId).name, "TactileConfig_All");
  EXPECT_EQ(Database().messages.size(), 1u + 3u * 7u);
  for (const DbcMessage& message : Database().messages) {
    EXPECT_FALSE(message.extended) << message.name;
    EXPECT_EQ(message.length_bytes, 8u) << message.name;
  }
}

TEST(TactileDbcTest, SignalsOfOneLayoutDoNotOverlap) {
  for (const DbcMessage& message : Database().messages) {
    std::map<std::optional<std::uint32_t>, std::uint64_t> used_by_layout;
    for (const DbcSignal& signal : message.signals) {
      ASSERT_TRUE(signal.little_endian) << message.name << "." << signal.name;
      const std::uint64_t mask =
          (signal.length_bits == 64 ? ~0ull : ((1ull << signal.length_bits) - 1))
          << signal.start_bit;
      std::uint64_t& used = used_by_layout[signal.multiplex_value];
      EXPECT_EQ(used & mask, 0u) << message.name << "." << signal.name;
      used |= mask;
    }
  }
}

TEST(TactileDbcTest, RandomSamplesReadTheSameThroughTheDbc) {
  std::mt19937 rng(11);
  for (std::uint8_t node = tactile_bus::kFirstNodeId; node <= tactile_bus::kReferenceNodeId;
       ++node) {
    for (int trial = 0; trial < 200; ++trial) {
      TactileSample sample;
      sample.node_id = node;
      for (std::uint16_t& word : sample.code) word = static_cast<std::uint16_t>(rng());
      sample.sequence = static_cast<std::uint8_t>(rng());
      sample.status = static_cast<std::uint8_t>(rng() & 0x0F);  // the defined bits

      const SignalValues values =
          ReadSignals(Message(tactile_bus::kSampleBaseId + node), EncodeTactileSample(sample));

      ExpectSignals(values,
                    {{"X_code", sample.code[0]},
                     {"Y_code", sample.code[1]},
                     {"Z_code", sample.code[2]},
                     {"Sequence", sample.sequence},
                     {"Saturated", Bit(sample.status, tactile_bus::kSampleSaturated)},
                     {"ConversionError", Bit(sample.status, tactile_bus::kSampleConversionError)},
                     {"Stale", Bit(sample.status, tactile_bus::kSampleStale)},
                     {"Tare", Bit(sample.status, tactile_bus::kSampleTare)}},
                    "node " + std::to_string(node));
    }
  }
}

TEST(TactileDbcTest, RandomStatusesReadTheSameThroughTheDbc) {
  std::mt19937 rng(12);
  for (std::uint8_t node = tactile_bus::kFirstNodeId; node <= tactile_bus::kReferenceNodeId;
       ++node) {
    for (int trial = 0; trial < 200; ++trial) {
      TactileStatus status;
      status.node_id = node;
      status.temperature_centi_c = static_cast<std::int16_t>(rng());
      status.flags = static_cast<std::uint8_t>(rng() & 0x1F);
      status.gain_sel = static_cast<std::uint8_t>(rng() % 8);
      status.resolution = static_cast<std::uint8_t>(rng() % 4);
      status.rate_code = static_cast<std::uint8_t>(rng() % tactile_bus::kRateHzByCode.size());
      status.rx_error_count = static_cast<std::uint8_t>(rng());
      status.firmware_version = static_cast<std::uint8_t>(rng());

      const SignalValues values =
          ReadSignals(Message(tactile_bus::kStatusBaseId + node), EncodeTactileStatus(status));

      ExpectSignals(values,
                    {{"Temperature", status.temperature_centi_c * 0.01},
                     {"ChipError", Bit(status.flags, tactile_bus::kFlagChipError)},
                     {"ConfigPending", Bit(status.flags, tactile_bus::kFlagConfigPending)},
                     {"CommandRejected", Bit(status.flags, tactile_bus::kFlagCommandRejected)},
                     {"TarePending", Bit(status.flags, tactile_bus::kFlagTarePending)},
                     {"ForwardOverflow", Bit(status.flags, tactile_bus::kFlagForwardOverflow)},
                     {"GainSel", status.gain_sel},
                     {"Resolution", status.resolution},
                     {"RateCode", status.rate_code},
                     {"RxErrorCount", status.rx_error_count},
                     {"FirmwareVersion", status.firmware_version}},
                    "node " + std::to_string(node));
    }
  }
}

TEST(TactileDbcTest, RandomCommandsReadTheSameThroughTheDbc) {
  std::mt19937 rng(13);
  for (std::uint8_t node = tactile_bus::kBroadcastNodeId; node <= tactile_bus::kReferenceNodeId;
       ++node) {
    for (int trial = 0; trial < 200; ++trial) {
      TactileConfigCommand command;
      command.node_id = node;
      command.command = static_cast<TactileCommand>(1 + rng() % 5);
      SignalValues expected = {{"Command", double(static_cast<std::uint8_t>(command.command))}};
      switch (command.command) {
        case TactileCommand::kSetRate:
          command.rate_hz = tactile_bus::kRateHzByCode[rng() % tactile_bus::kRateHzByCode.size()];
          expected["RateHz"] = command.rate_hz;
          break;
        case TactileCommand::kSetGain:
          command.gain_sel = static_cast<std::uint8_t>(rng() % 8);
          expected["GainSel"] = command.gain_sel;
          break;
        case TactileCommand::kSetResolution:
          command.resolution = static_cast<std::uint8_t>(rng() % 4);
          expected["Resolution"] = command.resolution;
          break;
        default:
          break;
      }

      const SignalValues values =
          ReadSignals(Message(tactile_bus::kConfigBaseId + node), EncodeTactileConfig(command));

      ExpectSignals(values, expected, "node " + std::to_string(node));
    }
  }
}

}  // namespace
}  // namespace hilrig::rig
