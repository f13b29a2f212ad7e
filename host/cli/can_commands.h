// `listen`: the frames on a real or emulated CAN bus, opened by URI (rig/can_open.h), printed as
// candump log lines as they arrive, so any backend -- SocketCAN, a gs_usb adapter, the loopback
// UDP bus -- can be watched from the command line. A bad URI is exit 2 with the URI and the cause.
#pragma once

#include <string>
#include <vector>

#include "host/cli/cli_args.h"

namespace hilrig::host {

// hilrig listen --can URI [--frames N]: until N frames were printed or a stop is requested.
int ListenCommand(const std::vector<std::string>& args, const CliStreams& io);

}  // namespace hilrig::host
