// A pseudo-terminal pair as a serial line between two processes on one machine: the rig keeps the
// master as its end, a DUT process opens the slave's path as it would a board's serial device.
// It is the fake of a USB serial port for a link that drives a board in real time (the MAVLink
// HITL link and PX4's stand-in on it). Errors name the call that failed and why.
#pragma once

#include <memory>
#include <string>

#include "host/link/byte_stream.h"
#include "rig/result.h"

namespace hilrig::host {

struct PseudoTerminal {
  std::unique_ptr<ByteStream> master;  // non-blocking
  std::string slave_path;              // e.g. /dev/pts/7, raw (no echo, no line editing)
  // The slave held open in raw mode until the peer has opened it: while no process holds the
  // slave, reading the master fails. Reset it once the peer is there.
  std::shared_ptr<void> slave_hold;
};

// Opens a pair. Allocates; not on a per-step path.
rig::Result<PseudoTerminal> OpenPseudoTerminal();

}  // namespace hilrig::host
