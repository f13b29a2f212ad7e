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

// Opens `device` 8N1, no flow control, raw (no echo, no line editing, no CR/LF mapping) at `baud`.
rig::Result<std::unique_ptr<ByteStream>> OpenSerialPort(const std::string& device, unsigned baud);

// Connects to host:port, waiting at most timeout_ms for the peer to accept.
rig::Result<std::unique_ptr<ByteStream>> ConnectTcpStream(const std::string& host,
                                                          std::uint16_t port, int timeout_ms);

// A TCP port on 127.0.0.1 that was free a moment ago, for a child process to listen on.
rig::Result<std::uint16_t> FreeLoopbackPort();

}  // namespace hilrig::host
