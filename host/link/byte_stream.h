// A bidirectional byte stream with deadlines: the transport under the serial HIL link, whatever
// carries it (a board's UART or USB CDC device, an emulated MCU's USART behind a TCP chardev, an
// in-memory pipe in tests). Writes take all bytes or fail; reads return what has arrived, waiting
// at most a timeout. A closed peer and an I/O failure are values, never exceptions or signals, so a
// watchdog above can name them. Streams are opened by name (OpenSerialPort, ConnectTcpStream) and
// closed by destruction.
//
// Threading: one stream is used from one thread at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "rig/result.h"

namespace hilrig::host {

enum class StreamStatus {
  kData,     // `bytes` bytes were read (at least one)
  kTimeout,  // nothing arrived before the deadline (or, with timeout 0, nothing was waiting)
  kClosed,   // the peer hung up (end of file, a reset connection, a vanished device)
  kError,    // the read failed; `error` says why
};

struct StreamRead {
  StreamStatus status = StreamStatus::kTimeout;
  std::size_t bytes = 0;
  std::string error;
};

class ByteStream {
 public:
  virtual ~ByteStream() = default;
  // Writes every byte, waiting at most timeout_ms for the stream to take them. An error names the
  // stream and the cause; code kLinkClosed when the peer hung up.
  virtual rig::Result<void> WriteAll(std::span<const std::uint8_t> bytes, int timeout_ms) = 0;
  // Reads what is there into `out`, waiting at most timeout_ms (0: do not wait) for a first byte.
  virtual StreamRead ReadSome(std::span<std::uint8_t> out, int timeout_ms) = 0;
  // What the stream was opened as ("/dev/ttyACM0 at 2000000 baud", "tcp 127.0.0.1:4000").
  virtual std::string name() const = 0;
};

}  // namespace hilrig::host
