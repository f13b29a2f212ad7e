#include <fcntl.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <cerrno>
#include <charconv>

#include "host/link/fd_byte_stream.h"
#include "host/link/open_byte_stream.h"

namespace hilrig::host {
namespace {

namespace asio = boost::asio;

struct SerialPort {
  asio::io_context io;
  asio::serial_port port{io};
};

}  // namespace

rig::Result<unsigned> ParseBaud(const std::string& text) {
  unsigned baud = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), baud);
  if (error != std::errc() || end != text.data() + text.size() || baud == 0 ||
      baud > kMaxSerialBaud) {
    return rig::MakeError("baud \"" + text + "\" is not a whole number in 1.." +
                          std::to_string(kMaxSerialBaud));
  }
  return baud;
}

rig::Result<SerialDeviceSpec> ParseSerialDevice(const std::string& text, unsigned default_baud) {
  const std::size_t comma = text.find(',');
  SerialDeviceSpec spec{text.substr(0, comma), default_baud};
  if (spec.device.empty()) return rig::MakeError("no device");
  if (comma == std::string::npos) return spec;
  const std::string option = text.substr(comma + 1);
  if (!option.starts_with("baud=")) {
    return rig::MakeError("unknown option \"" + option + "\" (expected baud=N)");
  }
  auto baud = ParseBaud(option.substr(5));
  if (!baud) return baud.error();
  spec.baud = baud.value();
  return spec;
}

rig::Result<std::unique_ptr<ByteStream>> OpenSerialPort(const std::string& device, unsigned baud) {
  auto serial = std::make_shared<SerialPort>();
  boost::system::error_code error;
  const auto fail = [&](const char* what) -> rig::Result<std::unique_ptr<ByteStream>> {
    return rig::MakeError(rig::ErrorCode::kIo,
                          "serial port " + device + ": " + what + ": " + error.message());
  };
  // Asio opens the device in raw mode, 8 data bits, no parity.
  if (serial->port.open(device, error)) return fail("open");
  if (serial->port.set_option(asio::serial_port::baud_rate(baud), error)) {
    return fail(("baud rate " + std::to_string(baud)).c_str());
  }
  using Port = asio::serial_port;
  serial->port.set_option(Port::character_size(8), error);
  if (!error) serial->port.set_option(Port::parity(Port::parity::none), error);
  if (!error) serial->port.set_option(Port::stop_bits(Port::stop_bits::one), error);
  if (!error) serial->port.set_option(Port::flow_control(Port::flow_control::none), error);
  if (error) return fail("line settings");
  const int fd = serial->port.native_handle();
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags < 0 || ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) != 0) {
    error.assign(errno, boost::system::system_category());
    return fail("non-blocking mode");
  }
  return std::unique_ptr<ByteStream>(std::make_unique<FdByteStream>(
      fd, /*socket=*/false, device + " at " + std::to_string(baud) + " baud", std::move(serial)));
}

}  // namespace hilrig::host
