// `hilrig replay RUN_DIR|RUN.mcap`: a run's recorded DUT traffic replayed on a DUT, open loop.
//   hilrig replay RUN [--dut KIND ...] [--set PATH=VALUE,...] [--tolerance T] [--out DIR]
// Prints, per output of the DUT's command, the largest difference from the recording and the
// first tick past the tolerance; writes replay.json into DIR if asked; exits 0 when no output
// parted, 1 when one did or the DUT failed a step (or the replay was interrupted), 2 for bad
// usage, a log that cannot be read or a recorded spec the overrides break.
#pragma once

#include <string>
#include <vector>

#include "host/cli/cli_args.h"

namespace hilrig::host {

extern const char kReplayUsage[];

int ReplayCommand(const std::vector<std::string>& args, const CliStreams& io);

}  // namespace hilrig::host
