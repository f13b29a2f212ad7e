// Where a serial DUT's lines come from, as `hilrig run --dut` names them: a board on serial
// devices (`serial:/dev/ttyACM0[,baud=N][,bridge=/dev/ttyUSB0][,bridge_baud=N]`), or the firmware
// image on QEMU's STM32F405 (`qemu`), its USART1 (the HIL link) and USART2 (the sensor bridge) on
// loopback TCP chardevs.
#pragma once

#include <optional>
#include <string>

#include "dut_fw/serial_line_rates.h"
#include "host/linked_dut/serial_dut.h"
#include "rig/result.h"

namespace hilrig::host {

// The defaults are the firmware image's rates (dut_fw/serial_line_rates.h).
struct SerialPortSpec {
  std::string device;
  unsigned baud = dut_fw::kLinkBaud;
  std::string bridge_device;  // empty: no sensor bridge wired
  unsigned bridge_baud = dut_fw::kBridgeBaud;
  // --can socketcan:IFACE: the board reads its sensors on its own CAN port, wired to IFACE; empty:
  // on the bridge line.
  std::string can_uri;
};

// Parses "serial:DEVICE[,baud=N][,bridge=DEVICE][,bridge_baud=N]"; errors name the part that is
// wrong.
rig::Result<SerialPortSpec> ParseSerialPortSpec(const std::string& spec);
// Opens the link at `baud`, the bridge, if any, at `bridge_baud`, and the CAN bus, if any.
SerialLineOpener SerialPortLines(const SerialPortSpec& spec);

inline constexpr const char* kTargetImageName = "dut_fw_stm32f405.elf";

struct QemuTarget {
  std::string image_path;
  std::string qemu_path;  // empty: qemu-system-arm from PATH
};

// The firmware image `explicit_path` names (it must exist), or the one ./scripts/build-target
// makes: build-target/dut_fw_stm32f405.elf in the source tree above the running executable
// (build/bin/), or next to the executable. The error lists where it looked and how to build one.
rig::Result<std::string> FindTargetImage(const std::optional<std::string>& explicit_path);
// Starts qemu-system-arm on the image (virtual time: -icount shift=0) with both USARTs on loopback
// TCP chardevs and connects to them; the emulator is ended with the DUT.
SerialLineOpener QemuLines(const QemuTarget& target);

}  // namespace hilrig::host
