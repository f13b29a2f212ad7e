// Opening the byte streams a serial HIL link runs on, by name: a serial device in raw mode at a
// baud rate (a board's UART adapter or USB CDC port, or a pseudo-terminal), or a TCP connection
// (an emulator's serial port on a `-serial tcp:` chardev). Errors name the device or address and
// the cause.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "host/link/byte_stream.h"
#include "rig/result.h"

namespace hilrig::host {

// The fastest baud a command line may name: USB CDC ports accept any number, UARTs far less.
inline constexpr unsigned kMaxSerialBaud = 12'000'000;

// A baud rate as a command line writes it: a whole number in 1..kMaxSerialBaud.
rig::Result<unsigned> ParseBaud(const std::string& text);

// A serial device as a command line names it, "DEVICE[,baud=N]"; `default_baud` when no baud is
// given. The errors say what is wrong ("no device", "unknown option ..."), the caller where.
struct SerialDeviceSpec {
  std::string device;
  unsigned baud = 0;
};
rig::Result<SerialDeviceSpec> ParseSerialDevice(const std::string& text, unsigned default_baud);

// Opens `device` 8N1, no flow control, raw (no echo, no line editing, no CR/LF mapping) at `baud`.
rig::Result<std::unique_ptr<ByteStream>> OpenSerialPort(const std::string& device, unsigned baud);

// Connects to host:port, waiting at most timeout_ms for the peer to accept.
rig::Result<std::unique_ptr<ByteStream>> ConnectTcpStream(const std::string& host,
                                                          std::uint16_t port, int timeout_ms);

// A TCP port on 127.0.0.1 that was free a moment ago, for a child process to listen on.
rig::Result<std::uint16_t> FreeLoopbackPort();

}  // namespace hilrig::host
