// Connecting a Boost.Asio TCP socket within a deadline, shared by the link's TCP transports (the
// HIL link to a DUT process, the byte stream to an emulator's serial chardev). Included by .cc
// files of host/link only, so that Boost.Asio stays out of every header other libraries read.
#pragma once

#include <atomic>
#include <boost/asio/ip/tcp.hpp>
#include <cstdint>
#include <string>

#include "rig/result.h"

namespace hilrig::host {

// Opens `socket` non-blocking and connects it to host:port with TCP_NODELAY, waiting at most
// timeout_ms, and less when `stop_requested` (may be null) is set: it is looked at every 100 ms.
// Errors start with `what` ("link connect to 127.0.0.1:4000: Connection refused"); code kTimeout
// when the deadline passed, kInterrupted when a stop was requested first.
rig::Result<void> ConnectWithin(boost::asio::ip::tcp::socket& socket, const std::string& host,
                                std::uint16_t port, int timeout_ms, const std::string& what,
                                const std::atomic<bool>* stop_requested = nullptr);

}  // namespace hilrig::host
