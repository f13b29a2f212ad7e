// The rates of the two serial lines between the rig and a board: the HIL link and the sensor
// nodes' UART bridge, 8N1. The firmware image sets them, and `hilrig run --dut serial:` and
// `dut_emu --serial` open their lines at them unless told otherwise, so a board and the rig agree
// out of the box. The link carries up to 157 framed bytes per command board to runner (six pads in
// contact), 1.57 Mbaud at 1 kHz control; 2 Mbaud leaves room and divides the STM32F405's 84 MHz
// APB2 exactly. The bridge carries about 50 kbaud (seven nodes at 50 Hz); 921600 baud is a rate
// every USB-UART adapter has. Sizing: docs/target.md.
#pragma once

#include <cstdint>

namespace hilrig::dut_fw {

inline constexpr std::uint32_t kLinkBaud = 2'000'000;
inline constexpr std::uint32_t kBridgeBaud = 921'600;

}  // namespace hilrig::dut_fw
