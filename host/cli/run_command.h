// `hilrig run`: one scenario file, or every scenario file in a folder, through the run pipeline
// (host/pipeline/run_pipeline.h), against the DUT `--dut` names (host/linked_dut/dut_choice.h).
//   hilrig run FILE.textproto|DIR/ [--out DIR] [--seed N] [--set PATH=VALUE,...] [--duration-s S]
//              [--dut KIND [...]] [--realtime [--rt-priority N]] [--no-reference]
//              [--reference-cache DIR]
// Prints each envelope's and check's line and the run's timing; a folder also gets a summary
// table and DIR/index.html. Exit codes: 0 every check met its expected verdict, 1 one did not or
// the run was cut short, 2 bad input or usage.
#pragma once

#include <string>
#include <vector>

#include "host/cli/cli_args.h"
#include "host/dut/dut_port.h"
#include "rig/result.h"

namespace hilrig::host {

// The lines of `hilrig help` about run, each ending in a newline.
extern const char kRunUsage[];

int RunCommand(const std::vector<std::string>& args, const CliStreams& io);

// The DUT that --dut and its options name (host/linked_dut/dut_choice.h), unset for the default
// in-process one; its waits end on the command's stop request and are announced on `io.err`.
// Fails on an option the choice refuses. `hilrig replay` takes the same options.
rig::Result<DutFactory> ParseDutOptions(const CliArgs& cli, bool realtime, const CliStreams& io);

}  // namespace hilrig::host
