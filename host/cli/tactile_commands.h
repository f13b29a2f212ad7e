// The tactile-sensing subcommands of hilrig: `calibrate` (the lab procedure of the fixtures:
// compensation fit, F/T jig, no-load jig; writes calibration.textproto), `accuracy` (held-out loads
// over an attitude sweep, with and without geomagnetic compensation; writes accuracy.json) and
// `decode` (S from field readings on stdin, for debugging real sensors).
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "host/cli/cli_args.h"

namespace hilrig::host {

int CalibrateCommand(const std::vector<std::string>& args, const CliStreams& io);
int AccuracyCommand(const std::vector<std::string>& args, const CliStreams& io);
int DecodeCommand(const std::vector<std::string>& args, const CliStreams& io, std::istream& in);
// `decode` on the process's standard input, which a stop request ends (exit 1, "interrupted")
// even while no line is coming.
int DecodeStandardInput(const std::vector<std::string>& args, const CliStreams& io);

}  // namespace hilrig::host
