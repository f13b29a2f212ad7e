// The lines of a DUT that dials the rig: a program that speaks the serial link's framing and
// messages (the DUT-side library, dut_link/) over TCP instead of a tty, as `--dut exec:` and
// `--dut listen:` with `--dut-link line` choose. The rig listens, the link on PORT and the sensor
// bridge on PORT+1, and the DUT connects to both, link first; its hello must carry the run's link
// token (SerialLines::link_token), since anyone on the host can reach a TCP port. With a program
// the rig starts it (PROGRAM ARGS... --connect 127.0.0.1:PORT, the token in HILRIG_LINK_TOKEN) on
// free ports and ends it with the run; without one a person starts the DUT, told on `notes` where
// to dial and which token file to read.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "host/linked_dut/serial_dut.h"

namespace hilrig::host {

struct DialedLineSpec {
  std::optional<std::string> program;  // exec: a path or a name on PATH; unset: listen
  std::vector<std::string> program_args;
  std::string address = "127.0.0.1";  // listen: where to listen
  std::uint16_t port = 0;             // listen: the link's port (the bridge's is port + 1)
  std::string token_file;             // listen: read, or created when missing
  const std::atomic<bool>* stop_requested = nullptr;  // ends the wait for the DUT (may be null)
  std::ostream* notes = nullptr;  // where a listening run says how to start the DUT (may be null)
};

// Opens nothing until called; then waits at most the opener's timeout for both connections, and
// fails naming what is missing, the program's exit if it ended first, or the stop request.
SerialLineOpener DialedLines(const DialedLineSpec& spec);

}  // namespace hilrig::host
