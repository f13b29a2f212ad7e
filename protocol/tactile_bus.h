// The tactile bus protocol's numbers, once: the ids, lengths, status bits, flags, command codes and
// rates of the classic CAN frames the seven Hall sensor nodes and the host exchange
// (proto/TACTILE_PROTOCOL.md explains them, proto/tactile.dbc states them for other tools). Both
// ends include this header: the node firmware and the DUT's tactile front end in dut_fw/, and the
// host's codec in rig/tactile_protocol.h. Header-only and portable: constants and nothing else.
//
// All ids are standard 11-bit ids, and a lower id wins arbitration, so configuration commands
// (kConfigBaseId + node) beat samples (kSampleBaseId + node), which beat the 1 Hz status frames
// (kStatusBaseId + node), and within a kind node 1 beats node 7.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace hilrig::tactile_bus {

// Nodes 1..6 carry the pads; node 7 is the reference magnetometer.
inline constexpr std::uint8_t kFirstNodeId = 1;
inline constexpr std::uint8_t kLastTactileNodeId = 6;
inline constexpr std::uint8_t kReferenceNodeId = 7;
inline constexpr std::uint8_t kLastNodeId = kReferenceNodeId;
inline constexpr std::size_t kTactileNodeCount = kLastTactileNodeId - kFirstNodeId + 1;
inline constexpr std::uint8_t kBroadcastNodeId = 0;  // config commands only

inline constexpr std::uint16_t kConfigBaseId = 0x080;  // host -> node; +0 is broadcast
inline constexpr std::uint16_t kSampleBaseId = 0x100;  // node -> bus, one per sample
inline constexpr std::uint16_t kStatusBaseId = 0x180;  // node -> bus, 1 Hz and on command

inline constexpr std::uint8_t kSampleLength = 8;
inline constexpr std::uint8_t kStatusLength = 8;
inline constexpr std::uint8_t kConfigMinLength = 2;
inline constexpr std::uint8_t kConfigMaxLength = 8;

// Sample status bits. Bits a decoder does not know are passed through, so newer node firmware
// does not break an older host.
inline constexpr std::uint8_t kSampleSaturated = 1u << 0;        // an axis at a rail
inline constexpr std::uint8_t kSampleConversionError = 1u << 1;  // chip flagged ERROR
inline constexpr std::uint8_t kSampleStale = 1u << 2;            // chip did not answer: last result
inline constexpr std::uint8_t kSampleTare = 1u << 3;  // first sample after a zero request

// Status-frame flag bits.
inline constexpr std::uint8_t kFlagChipError = 1u << 0;        // last chip transaction failed
inline constexpr std::uint8_t kFlagConfigPending = 1u << 1;    // accepted, not yet on chip
inline constexpr std::uint8_t kFlagCommandRejected = 1u << 2;  // last command was invalid
inline constexpr std::uint8_t kFlagTarePending = 1u << 3;      // tare mark not yet sent
inline constexpr std::uint8_t kFlagForwardOverflow = 1u << 4;  // daisy-chain drop since last

// Configuration commands, the first byte of a config frame.
inline constexpr std::uint8_t kCommandSetRate = 1;        // u16 rate_hz, one of kRateHzByCode
inline constexpr std::uint8_t kCommandSetGain = 2;        // u8 gain_sel, 0..7
inline constexpr std::uint8_t kCommandSetResolution = 3;  // u8 resolution, 0..3
inline constexpr std::uint8_t kCommandZero = 4;   // tare: the next sample carries kSampleTare
inline constexpr std::uint8_t kCommandReset = 5;  // defaults restored, sequence restarts at 0

// The node's sample rates. The set-rate command carries Hz, the status frame the code; a rate not
// in this table is rejected, so host and node never disagree about what rate is running.
inline constexpr std::array<std::uint16_t, 11> kRateHzByCode = {0,   1,   10,  20,  25,  50,
                                                                100, 200, 250, 500, 1000};

// The node firmware's version in its status frame: major nibble, minor nibble (0x10 is 1.0).
inline constexpr std::uint8_t kFirmwareVersion = 0x10;

}  // namespace hilrig::tactile_bus
